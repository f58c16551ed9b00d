"""The built API reference documents every public name (run by ``make docs`` after Sphinx).

Every name in ``quatspline.__all__`` must have an anchor in the generated HTML: ``quatspline.NAME``
for functions, classes and constants, ``module-quatspline.NAME`` for modules. New public names
are picked up by ``docs/conf.py`` automatically; this test fails if one is not rendered.
"""

from __future__ import annotations

import inspect
import os
import re
from pathlib import Path

import pytest
import quatspline

BUILD = Path(os.environ.get("QUATSPLINE_DOCS_BUILD", Path(__file__).parent / "_build" / "html"))


@pytest.fixture(scope="module")
def anchors() -> set[str]:
    api = BUILD / "api"
    assert (api / "index.html").is_file(), f"no built docs in {BUILD} (run `make docs`)"
    found: set[str] = set()
    for page in api.rglob("*.html"):
        found.update(re.findall(r'id="([^"]+)"', page.read_text(encoding="utf-8")))
    return found


@pytest.mark.parametrize("name", quatspline.__all__)
def test_public_name_is_in_the_api_reference(name, anchors):
    obj = getattr(quatspline, name)
    anchor = f"module-quatspline.{name}" if inspect.ismodule(obj) else f"quatspline.{name}"
    assert anchor in anchors


def test_gallery_and_maths_pages_were_built():
    for page in ("auto_examples/index.html", "maths/c3.html", "conventions.html", "choosing.html"):
        assert (BUILD / page).is_file(), page
    figures = list((BUILD / "_images").glob("*.png"))
    assert len(figures) >= 8, f"expected the gallery and plot figures, got {len(figures)}"
