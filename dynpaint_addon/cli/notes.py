"""One voice (issue 27): how every command says what it guessed about its inputs.

Each command runs the same checks (core.input_rules.input_notes on a recipe's images, or the
part of them its inputs have) and prints each note as `note: …` on stderr, before its own
result line on stdout; errors stay one `error: …` line (cli.main). The add-on's Add reports
the same lines (blender/scenes/painting_scene.check_images).
"""
import sys

from ..core.input_rules import input_notes


def print_notes(notes):
    for note in notes:
        print(f"note: {note}", file=sys.stderr, flush=True)


def check_and_print(images, p):
    """input_notes(images, p), printed; raises ValueError for an image the settings cannot
    read (the command's `error:` line)."""
    print_notes(input_notes(images, p))


def figure_note(name, source):
    """What a figure mask was read from (make-shape inflate, integrate --mask)."""
    where = "its alpha" if source == "alpha" else \
        "its luminance" if source in ("luminance", "grey") else \
        f"its {source} channel (a mask painted in {source})"
    return f"{name}: the figure is where {where} is above ½"


def on_words(renderer):
    """' on RENDERER' for a command's result line where it knows what drew it (EEVEE's GPU, or
    a software renderer), else ''.

    >>> on_words("NVIDIA H200/PCIe/SSE2"), on_words("")
    (' on NVIDIA H200/PCIe/SSE2', '')
    """
    return f" on {renderer}" if renderer else ""
