"""Sphinx configuration: numpydoc docstrings, sphinx-gallery examples, an API reference
generated from ``quatspline.__all__`` (so new public names appear without editing the docs)."""

from __future__ import annotations

import inspect
import os
from pathlib import Path

import quatspline

HERE = Path(__file__).resolve().parent
os.environ.setdefault("MPLBACKEND", "Agg")

project = "quatspline"
author = "The quatspline developers"
copyright = "2026, The quatspline developers"  # noqa: A001 (Sphinx's name)
release = quatspline.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "matplotlib.sphinxext.plot_directive",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

templates_path = ["_templates"]
exclude_patterns = ["_build", "**.ipynb_checkpoints", "auto_examples/*.py", "**/*.md5"]
html_theme = "pydata_sphinx_theme"  # the theme of numpy and scipy's documentation
html_static_path = ["_static"]
html_css_files = ["wrap.css"]
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_title = f"quatspline {release}"
default_role = "code"
nitpicky = False

autosummary_generate = True
autodoc_typehints = "none"
autodoc_default_options = {"inherited-members": False}
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_use_plots = False

intersphinx_mapping: dict[str, tuple[str, None]] = {}
# Offline builds: no intersphinx inventories are fetched (CI has no network but registries).

plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 90)]
plot_rcparams = {"figure.figsize": (7.5, 3.6), "font.size": 9}

sphinx_gallery_conf = {
    "examples_dirs": str(HERE.parent / "examples"),
    "gallery_dirs": str(HERE / "auto_examples"),
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "show_memory": False,
    "matplotlib_animations": False,
}

# ---- the API reference, generated from quatspline.__all__ ----------------------------------
SECTIONS = {  # module (or package) of a name's definition → its section; longest prefix wins
    "quatspline.splines.joints": "Continuity certificate",
    "quatspline.splines.timing": "Retiming",
    "quatspline.splines.screw": "Poses",
    "quatspline.splines.se3": "Poses",
    "quatspline.splines.pose_bspline": "Poses",
    "quatspline.poses": "Poses",
    "quatspline.splines": "Splines",
    "quatspline.registry": "Splines by name",
    "quatspline.fitting": "Fitting",
    "quatspline.ops._fit": "Fitting",
    "quatspline.ops": "Operations on recordings",
    "quatspline.core.algebra": "Quaternion algebra",
    "quatspline.core.interpolate": "Two-key interpolation",
    "quatspline.core.convert": "Conversions",
    "quatspline.core.dualquat": "Dual quaternions",
    "quatspline.core.rigid": "Rigid bodies",
    "quatspline.core.metrics": "Metrics",
    "quatspline.core.averaging": "Means",
    "quatspline.core.integration": "Integration",
    "quatspline._util": "Engine settings",
    "quatspline._core": "Engine settings",
}


def _section(name: str, obj: object) -> str:
    if inspect.ismodule(obj):
        return "Modules"
    if not callable(obj):
        return "Constants"
    mod = getattr(obj, "__module__", None) or "quatspline"
    for prefix in sorted(SECTIONS, key=len, reverse=True):
        if mod == prefix or mod.startswith(prefix + "."):
            return SECTIONS[prefix]
    # a module added later: its own section, titled after the module
    return mod.rsplit(".", 1)[-1].strip("_").replace("_", " ").capitalize()


def write_api_reference() -> None:
    groups: dict[str, list[str]] = {}
    for name in quatspline.__all__:
        groups.setdefault(_section(name, getattr(quatspline, name)), []).append(name)
    order = list(dict.fromkeys([*SECTIONS.values(), *sorted(groups)]))
    order = [s for s in order if s not in ("Modules", "Constants")] + ["Modules", "Constants"]
    lines = [
        ".. This file is written by conf.py from quatspline.__all__; do not edit.",
        "",
        "API reference",
        "=============",
        "",
        ".. currentmodule:: quatspline",
        "",
        "Every public name of the package, generated from ``quatspline.__all__``. Quaternions",
        "are float64 arrays of shape ``(..., 4)``, scalar first; see :doc:`../conventions`.",
        "",
    ]
    for section in order:
        names = groups.get(section)
        if not names:
            continue
        lines += [section, "-" * len(section), ""]
        if section == "Constants":
            for n in names:
                lines += [f".. autodata:: {n}", "   :annotation:", ""]
            continue
        if section == "Modules":
            # one page per public submodule, written here (autosummary resolves a module
            # named like a stdlib one, e.g. ``io``, to the wrong module)
            gen = HERE / "api" / "generated"
            gen.mkdir(parents=True, exist_ok=True)
            lines += [".. toctree::", "   :maxdepth: 1", ""]
            for n in sorted(names):
                full = f"quatspline.{n}"
                page = "\n".join(
                    [
                        full,
                        "=" * len(full),
                        "",
                        f".. automodule:: {full}",
                        "   :members:",
                        "   :imported-members:",
                        "",
                    ]
                )
                path = gen / f"{full}.rst"
                if not path.exists() or path.read_text() != page:
                    path.write_text(page)
                lines.append(f"   generated/{full}")
            lines.append("")
            continue
        lines += [".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
        lines += [f"   {n}" for n in sorted(names, key=lambda s: (not s[0].isupper(), s))]
        lines.append("")
    text = "\n".join(lines)
    path = HERE / "api" / "index.rst"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


write_api_reference()
