"""``mechsynth explore``: an interactive explorer in the browser (optional extra
``mechsynth[explore]``: Panel and Bokeh).

:mod:`.model` holds the page's logic in plain Python (tested without a browser); :mod:`.app`
builds the page with Panel and serves it. This package imports neither Panel nor Bokeh: the
page's module is imported only by :func:`serve` (and ``mechsynth explore``).
"""

from __future__ import annotations

__all__ = ["serve", "PANEL_MISSING"]

#: the one-line message when the extra is not installed
PANEL_MISSING = (
    "mechsynth explore needs the optional extra 'explore' (Panel and Bokeh): "
    "pip install 'mechsynth[explore]'"
)


def serve(*args, **kwargs):
    """Start the explorer's server; see :func:`mechsynth.explore.app.serve`. Raises
    ``ImportError`` with :data:`PANEL_MISSING` when Panel is not installed."""
    try:
        import bokeh  # noqa: F401
        import panel  # noqa: F401
    except ImportError as exc:
        raise ImportError(PANEL_MISSING) from exc
    from .app import serve as _serve

    return _serve(*args, **kwargs)
