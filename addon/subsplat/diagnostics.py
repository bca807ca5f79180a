"""What tests and benchmarks read and switch: the figures of the last render and viewport, and the
test hooks. Nothing here changes an image.

Package level: subsplat.last_render_stats(), last_render_error(), last_render_passes(),
last_viewport() are these functions.
"""

# Scripts that render in background mode and want to handle failures themselves (tests) set
# subsplat.diagnostics.exit_on_error = False; otherwise a failed `blender -b` render exits with 1.
exit_on_error = True
# Tests and benchmarks set keep_passes = True to read last_render_passes().
keep_passes = False
# Tests set check_gl_state = True: each viewport draw and render compares the GL state before and
# after the library's calls (native.gl_state) and reports what changed, in last_viewport()
# ["gl_state_changes"] and last_render_stats()["gl_state_changes"].
check_gl_state = False

_last_stats = {}
_last_error = None
_last_passes = {}
_last_viewport = None


def last_render_stats():
    """Figures of the last SubSplat render, as a plain dict (a copy)."""
    return {key: (dict(value) if isinstance(value, dict) else value) for key, value in _last_stats.items()}


def last_render_error():
    """The message of the last failed render, or None."""
    return _last_error


def last_viewport():
    """Counters, stats and error of the most recently updated viewport (a copy; {} before one)."""
    if _last_viewport is None:
        return {}
    return {**_last_viewport.counters.as_dict(), "stats": dict(_last_viewport.stats), "error": _last_viewport.error}


def last_viewport_first_sample():
    """The first anti-aliasing sample's image of the most recently updated viewport, float32 (height,
    width, 4), bottom row first, or None before one (tests compare a fast material edit with Full)."""
    if _last_viewport is None or _last_viewport.first_sample is None:
        return None
    return _last_viewport.first_sample.copy()


def last_render_passes():
    """With keep_passes set: {"Combined": ..., "SubSplat Exitance": ...} of the last render, as
    float32 arrays (height, width, 4), bottom row first. Used by tests and bench/accuracy.py."""
    return dict(_last_passes)


def set_render_stats(stats):
    _last_stats.clear()
    _last_stats.update(stats)


def set_render_error(message):
    global _last_error
    _last_error = message


def set_render_passes(passes):
    _last_passes.clear()
    _last_passes.update(passes)


def set_viewport(session):
    global _last_viewport
    _last_viewport = session


def add_render_stat(name, value):
    _last_stats[name] = value
