"""docs/parameters.md is what docs/make_docs.py writes from params.py today (no stale copy)."""
import os

from conftest import REPO
from doc_generators import load_generator


def test_parameters_page_is_current():
    make_docs = load_generator("make_docs")
    page = open(os.path.join(REPO, "docs", "parameters.md"), encoding="utf-8").read()
    assert page == make_docs.parameters_page(make_docs.picture_index()), \
        "docs/parameters.md is stale: run docs/make_docs.py"
    for file, _ in make_docs.picture_index().values():
        assert os.path.isfile(os.path.join(REPO, "docs", "img", "params", file))

