# SPDX-License-Identifier: Apache-2.0
"""vdbmap from Python: the adaptive-TSDF integrator on numpy arrays, YAML pipelines, and
readers of vdbmap's outputs (docs/python.md).

    import vdbmap
    m = vdbmap.Map(voxel_size_m=0.1)          # the integrate.atsdf options and defaults
    m.integrate(points_L, T_W_L)              # (N, 3) float32/64, 4x4 pose
    vertices, triangles = m.extract_triangle_mesh()
    report = vdbmap.run("config/street.yaml", "out/run", overrides={"dataset.path": "seq"})
"""
from __future__ import annotations

import atexit
import json
import os
from typing import Any, Mapping, Optional

from ._vdbmap import (  # noqa: F401  (re-exported)
    ConfigError,
    DataError,
    Error,
    InvalidInputError,
    IoError,
    Map,
    PluginError,
    __version__,
)
from . import _vdbmap
from .readers import read_mesh, read_obj, read_ply, read_tile_index  # noqa: F401

__all__ = [
    "Map", "run", "read_mesh", "read_ply", "read_obj", "read_tile_index",
    "Error", "ConfigError", "PluginError", "DataError", "IoError", "InvalidInputError",
    "__version__",
]

# vdbmap's log lines go to Python's logging (logger "vdbmap") while the module is loaded.
_vdbmap._log_to_python(True)
atexit.register(_vdbmap._log_to_python, False)


def _override_text(key: str, value: Any) -> str:
    """`key=value` as `vdbmap run --set` takes it; the value as JSON (which is YAML)."""
    if not isinstance(key, str) or not key:
        raise ValueError(f"overrides: keys must be non-empty strings, got {key!r}")
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    try:
        text = json.dumps(value)
    except TypeError as e:
        raise ValueError(f"overrides[{key!r}]: {e}") from None
    return f"{key}={text}"


def run(config_path: "str | os.PathLike[str]", output_dir: "str | os.PathLike[str] | None" = None,
        overrides: Optional[Mapping[str, Any]] = None, threads: Optional[int] = None,
        quiet: bool = True) -> dict:
    """Runs a YAML pipeline as `vdbmap run` does and returns report.json as a dict.

    overrides: {"dataset.path": "seq", "integrate.atsdf.voxel_size_m": 0.05} (the `--set`
    paths; a relative dataset.path is relative to the current directory). threads: worker
    threads (None = all cores). Log lines go to the "vdbmap" logger; quiet=False also draws
    progress bars on a terminal. Raises ConfigError (bad config), DataError (bad data) ...
    """
    if threads is not None and (not isinstance(threads, int) or threads < 1):
        raise ValueError(f"threads: expected None or an int >= 1, got {threads!r}")
    sets = [_override_text(k, v) for k, v in (overrides or {}).items()]
    out = "" if output_dir is None else os.fspath(output_dir)
    text = _vdbmap._run(os.fspath(config_path), out, sets, threads or 0, bool(quiet))
    return json.loads(text)
