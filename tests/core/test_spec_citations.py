"""The spec is in the repository and the code's § citations point into it (issue 14)."""
import glob
import os
import re

from conftest import REPO

SPEC = os.path.join(REPO, "docs", "pipeline.md")


def test_every_cited_section_exists_in_docs_pipeline_md():
    sections = set(re.findall(r"^## §(\d+)", open(SPEC, encoding="utf-8").read(), re.M))
    assert {str(n) for n in range(15)} <= sections
    sources = [p for ext in ("py", "h", "osl") for p in
               glob.glob(os.path.join(REPO, "**", f"*.{ext}"), recursive=True)
               if f"{os.sep}.venv{os.sep}" not in p]
    cited = {}
    for path in sources:
        for n in re.findall(r"§(\d+)", open(path, encoding="utf-8").read()):
            cited.setdefault(n, path)
    assert cited and {n: p for n, p in cited.items() if n not in sections} == {}


def test_the_blender_facts_are_in_the_repository():
    notes = open(os.path.join(REPO, "docs", "blender-notes.md"), encoding="utf-8").read()
    assert "frame_change_post" in notes and "Map Range" in notes
