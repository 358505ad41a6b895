"""The filter table (filter_geofilter/filter_table.cpp) as the build wrote it: filter names,
parameters, types and defaults, so that no Python harness repeats them.

The build writes filter_table.json into its build directory; ctest passes its path as
$GEOFILTER_FILTER_TABLE. Outside ctest the default build's (build/filter_table.json) is read.
"""

import json
import os

_DEFAULT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "filter_table.json")


def _load():
    path = os.environ.get("GEOFILTER_FILTER_TABLE", _DEFAULT)
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise RuntimeError(f"no filter table at {path} ({e.strerror}): build the geofilter_filter_table target"
                           " (any build of the project does) or set GEOFILTER_FILTER_TABLE") from None


TABLE = _load()  # [{name, python_name, cli_name, kind, [reference,] parameters: [{name, type, default, choices}]}]


def by_kind(*kinds):
    return [f for f in TABLE if f["kind"] in kinds]


def find(name):
    """The entry with this MeshLab, python or cli name."""
    for f in TABLE:
        if name in (f["name"], f["python_name"], f["cli_name"]):
            return f
    raise KeyError(f"no GeoFilter filter named {name!r}")
