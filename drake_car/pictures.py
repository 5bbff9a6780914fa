"""Pictures written beside results: the Diagram as SVG (Graphviz) and the car in Meshcat (HTML)."""

import shutil
import subprocess
from pathlib import Path

from pydrake.geometry import Meshcat, MeshcatParams
from pydrake.systems.analysis import Simulator


def write_diagram_svg(diagram, path, *, max_depth=1):
    """Draws ``diagram`` with the plant's ports split by input/output, as SVG."""
    dot = shutil.which("dot")
    if dot is None:
        raise RuntimeError("Graphviz's 'dot' is not installed; run tools/setup.sh "
                           "(or install the 'graphviz' package) to draw the diagram")
    text = diagram.GetGraphvizString(max_depth=max_depth, options={"plant/split": "I/O"})
    svg = subprocess.run([dot, "-Tsvg"], input=text, capture_output=True, text=True,
                         check=True, timeout=60).stdout
    Path(path).write_text(svg)
    Path(path).with_suffix(".dot").write_text(text)


def start_meshcat():
    """A Meshcat server on localhost (any free port)."""
    params = MeshcatParams()
    params.host = "localhost"
    params.port = 0  # pick a free one
    return Meshcat(params)


def record_html(meshcat, simulator: Simulator, end_time_s, path):
    """Simulates to ``end_time_s`` while recording, then saves a self-contained replay page."""
    meshcat.StartRecording(frames_per_second=32.0)
    simulator.AdvanceTo(end_time_s)
    meshcat.StopRecording()
    meshcat.PublishRecording()
    Path(path).write_text(meshcat.StaticHtml())
