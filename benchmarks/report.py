"""Shared by the benchmarks: print the Markdown page and write it where asked."""
import os


def publish(lines, path=None):
    text = "\n".join(lines) + "\n"
    print(text)
    if path:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    return text
