"""``quatspline view``: attitude design in the browser.

A small local web application (Starlette served by uvicorn) around
:func:`quatspline.ops.design.evaluate`: the rigid body moving along the spline in 3D, the traces
of its body axes on the unit sphere, live controls for the method's parameters, the sizes of
ω, α and jerk against time, the continuity certificate per joint, a second method to compare,
key editing with undo and redo, and export (CSV, JSON, glTF) with the Python call that
reproduces the design.

Security: the server binds to 127.0.0.1, every request must carry the random token of the
printed URL (as Jupyter does), requests from other origins or with a foreign ``Host`` header
are refused, and only the page's own assets and the file named on the command line are served.
Designs and exports are computed in worker processes with a bounded queue and a time limit,
request bodies and every request's work are bounded, and idle, slow or excess connections are
closed, so no client can wedge the server (limits: :mod:`quatspline.viewer.server`).

The page's JavaScript (three.js, uPlot) is installed from npm when the package is built and
ships inside it; nothing is fetched from the internet at run time. Needs the ``viewer``
extra: ``pip install "quatspline[viewer]"``.
"""

from __future__ import annotations

from .server import VIEWER_HINT, create_app, serve

__all__ = ["VIEWER_HINT", "create_app", "serve"]
