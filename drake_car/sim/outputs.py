"""Writing results: all-or-nothing output folders, lossless CSV, JSON with provenance, the
Diagram as SVG, and a run's own files.

An output folder is written all or nothing: ``output_folder(out)`` checks the target at once
(an existing file, a folder that is not a drake_car output, an unwritable place are refused
before any work), takes a lock (a second writer to the same folder is refused), and yields a
temporary folder beside the target; on success the target is replaced by it whole (a reused
folder never mixes old and new files), on any error, Ctrl-C or SIGTERM the temporary folder is
removed. Temporary folders and locks of killed runs are removed by the next run (and ignored
by git: ``.gitignore``).
"""

import contextlib
import csv
import datetime
import importlib.metadata
import json
import math
import os
import platform
import shutil
import signal
import subprocess
import sys
import uuid
from pathlib import Path

import numpy as np

MARKER = ".drake_car_output"  # in every folder this module wrote


class OutputError(ValueError):
    """The output folder cannot be used; the message names it and why."""


def check_output_target(out_dir):
    """Refuses an output target that cannot be written as a whole, before any work."""
    out_dir = Path(out_dir)
    if out_dir.is_file() or (out_dir.exists() and not out_dir.is_dir()):
        raise OutputError(f"--out {out_dir}: is a file, not a folder")
    if out_dir.is_dir() and any(out_dir.iterdir()) and not (out_dir / MARKER).is_file():
        raise OutputError(f"--out {out_dir}: exists, is not empty and was not written by "
                          "drake_car; choose a new or empty folder (it would be replaced whole)")
    parent = out_dir.parent
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"--out {out_dir}: {probe} is not a writable folder")


def _pid_alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_stale(parent, name):
    """Temporary folders and locks of runs that were killed."""
    for item in parent.glob(f".{name}.partial-*"):
        try:
            pid = int(item.name.split(".partial-")[1].split("-")[0])
        except (IndexError, ValueError):
            continue
        if not _pid_alive(pid):
            shutil.rmtree(item, ignore_errors=True)


@contextlib.contextmanager
def _lock(parent, name):
    lock = parent / f".{name}.lock"
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            try:
                pid = int(lock.read_text().strip() or "0")
            except (OSError, ValueError):
                pid = 0
            if pid and _pid_alive(pid) and pid != os.getpid():
                raise OutputError(f"--out {parent / name}: another run (pid {pid}) is writing "
                                  "to it; wait for it or choose another folder") from None
            lock.unlink(missing_ok=True)  # a killed run's lock
            continue
        with os.fdopen(fd, "w") as f:
            f.write(str(os.getpid()))
        break
    else:
        raise OutputError(f"--out {parent / name}: cannot take the lock {lock}")
    try:
        yield
    finally:
        lock.unlink(missing_ok=True)


@contextlib.contextmanager
def terminate_as_exit(*, once=False):
    """SIGTERM raises SystemExit here, so ``finally`` blocks clean up as on Ctrl-C; ``once``:
    a second SIGTERM during that cleanup is ignored."""
    def handler(signum, frame):
        if once:
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise SystemExit(128 + signum)
    try:
        previous = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread: leave the signal alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def output_folder(out_dir):
    """Yields a temporary folder beside ``out_dir``; on success it replaces ``out_dir`` whole;
    on any error (or SIGINT/SIGTERM) it is removed and ``out_dir`` is left as it was."""
    out_dir = Path(out_dir).absolute()
    check_output_target(out_dir)
    parent, name = out_dir.parent, out_dir.name
    parent.mkdir(parents=True, exist_ok=True)
    _remove_stale(parent, name)
    with terminate_as_exit(), _lock(parent, name):
        staging = parent / f".{name}.partial-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        staging.mkdir()
        try:
            (staging / MARKER).write_text("written by drake_car; replaced whole by the next "
                                          "run that writes here\n")
            yield staging
            check_output_target(out_dir)  # still a folder we may replace
            old = None
            if out_dir.exists():
                old = parent / f".{name}.partial-{os.getpid()}-old-{uuid.uuid4().hex[:8]}"
                out_dir.rename(old)
            staging.rename(out_dir)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        finally:
            if staging.exists():
                shutil.rmtree(staging, ignore_errors=True)


def provenance(**extra):
    """How a result was made: command, versions (drake_car's as installed, None if it is not),
    the git commit of drake_car's source and whether its working tree had uncommitted changes
    (both None when the source is not in a git checkout: ``source_checkout``), time."""
    commit, dirty = source_checkout()
    info = {
        "command": " ".join([Path(sys.argv[0]).name] + sys.argv[1:]),
        "git_commit": commit,
        "dirty": dirty,
        "drake_car": _installed_version("drake_car"),
        "drake": _installed_version("drake") or "unknown",
        "python": platform.python_version(),
        "numpy": _installed_version("numpy") or "unknown",
        "machine": platform.machine(),
        "created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    info.update(extra)
    return info


def source_checkout():
    """(commit, dirty) of the git checkout that holds drake_car's source: its HEAD, and whether
    tracked files have uncommitted changes. (None, None) when there is none: no git, or the
    package is not a tracked folder of that checkout (an installed copy inside some other
    repository, say in its ignored virtual environment, does not take that repository's)."""
    package = Path(__file__).resolve().parents[1]
    found = (_git(package, "rev-parse", "--show-toplevel", "HEAD") or "").splitlines()
    if len(found) != 2:
        return None, None
    top, commit = Path(found[0]).resolve(), found[1].strip()
    if top not in package.parents or not _git(
            top, "ls-files", "--", str(package.relative_to(top) / "__init__.py")):
        return None, None
    changes = _git(top, "status", "--porcelain", "--untracked-files=no")
    return commit, None if changes is None else bool(changes)


def _git(folder, *args):
    """What ``git -C folder args`` printed, stripped; None if git is missing or fails."""
    try:
        done = subprocess.run(["git", "-C", str(folder), *args], capture_output=True,
                              text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def _installed_version(package):
    """``package``'s installed version (None if it is not installed)."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return None


def plain(value):
    """``value`` with numpy types and non-finite floats made JSON-ready."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(path, data):
    Path(path).write_text(json.dumps(plain(data), indent=2, sort_keys=False) + "\n")


def write_csv(path, columns: dict):
    """``columns``: name -> sequence (all the same length); strings or numbers. Floats are
    written with ``repr`` (shortest round-trip form): the CSV carries the run's bits."""
    names = list(columns)
    lengths = {len(columns[n]) for n in names}
    if len(lengths) > 1:
        raise ValueError(f"columns of different lengths: "
                         f"{ {n: len(columns[n]) for n in names} }")
    rows = zip(*(columns[n] for n in names))
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(names)
        for row in rows:
            writer.writerow([repr(float(x)) if isinstance(x, (float, np.floating)) else x
                             for x in row])


def read_csv(path):
    """Reads a CSV written by ``write_csv``: name -> numpy array (or list of str)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names, data = rows[0], rows[1:]
    out = {}
    for i, name in enumerate(names):
        values = [r[i] for r in data]
        try:
            out[name] = np.array([float(v) for v in values])
        except ValueError:
            out[name] = values
    return out


def write_diagram_svg(dot_text, path):
    """Draws Graphviz ``dot_text`` as SVG (and keeps the .dot beside it)."""
    dot = shutil.which("dot")
    if dot is None:
        raise OutputError("Graphviz's 'dot' is not installed; run tools/setup.sh (or install "
                          "the 'graphviz' package) to draw the diagram")
    svg = subprocess.run([dot, "-Tsvg"], input=dot_text, capture_output=True, text=True,
                         check=True, timeout=120).stdout
    Path(path).write_text(svg)
    Path(path).with_suffix(".dot").write_text(dot_text)


def write_run(run, folder, *, diagram=True):
    """A run's own files: history.csv, scene.yaml (the scene as it ran), run.json (how it went,
    provenance), diagram.svg and replay.html when there is one."""
    folder = Path(folder)
    write_csv(folder / "history.csv", run.history)
    (folder / "scene.yaml").write_text(run.scene_file_text)
    write_json(folder / "run.json", run.record() | {"provenance": provenance()})
    if diagram:
        write_diagram_svg(run.diagram_dot, folder / "diagram.svg")
    if run.replay_html is not None:
        (folder / "replay.html").write_text(run.replay_html)




# -- the Diagram at a glance ------------------------------------------------------------------

# Systems that only route signals: the overview draws their wires straight through them.
PLUMBING = ("Multiplexer", "Demultiplexer", "PassThrough", "ConstantVectorSource",
            "ConstantValueSource", "ExternallyAppliedSpatialForceMultiplexer")


def _dot_nodes_and_edges(dot_text):
    """Systems and wires of a Drake Graphviz drawing (``Diagram.GetGraphvizString``, one level,
    the plant's I/O split or not): {id: [type, name, {port: label}]}, [(src, port, dst, port)]."""
    import html
    import re

    def base(node_id):
        return node_id if node_id == "meshcat_in" else re.sub(r"(in|out)$", "", node_id)
    nodes = {}
    for node_id, body in re.findall(r"^(\w+) \[shape=none, border=0, label=<\n(.*?)\n>\];",
                                    dot_text, flags=re.S | re.M):
        kind = re.search(r"<B>(.*?)</B>", body)
        name = re.search(r"name=([^\n<]*)", body)
        ports = {p: html.unescape(re.sub(r"<[^>]+>", "", label)).strip()
                 for p, label in re.findall(r'<TD PORT="([uy]\d+)"[^>]*>(.*?)</TD>', body,
                                            flags=re.S)}
        merged = nodes.setdefault(base(node_id), [kind.group(1) if kind else node_id,
                                                  name.group(1).strip() if name else "", {}])
        merged[2].update(ports)
    edges = [(base(s), sp, base(d), dp) for s, sp, d, dp in re.findall(
        r"^(\w+)(?::(\w+))?(?::\w+)? -> (\w+)(?::(\w+))?", dot_text, flags=re.M)]
    return nodes, edges


def _fold_plumbing(nodes, edges):
    """Every routing system (``PLUMBING``) removed, its inputs wired to where its outputs
    went (a constant source feeding only such systems vanishes). Returns the folded names."""
    folded = []
    for node in [n for n, (kind, _, _) in nodes.items() if kind.split(".")[-1] in PLUMBING]:
        into = [e for e in edges if e[2] == node]
        out = [e for e in edges if e[0] == node]
        edges = [e for e in edges if node not in (e[0], e[2])]
        edges += [(s, sp, d, dp) for s, sp, _, _ in into for _, _, d, dp in out]
        folded.append(nodes.pop(node)[1] or node)
    return list(dict.fromkeys(edges)), folded


def diagram_overview_dot(dot_text, title="The Diagram at a glance"):
    """A readable drawing of a Drake Diagram's Graphviz text, left to right: every system once
    (the plant too, its inputs on the left and its outputs on the right), only the ports that
    are wired, the systems that only route signals folded into the wires, the loggers as one
    box."""
    import html
    nodes, edges = _dot_nodes_and_edges(dot_text)
    edges, folded = _fold_plumbing(nodes, edges)
    loggers = sorted(n for n, (kind, _, _) in nodes.items() if kind == "VectorLogSink")
    used = {(s, p) for s, p, _, _ in edges} | {(d, p) for _, _, d, p in edges}
    note = (f"<BR/><FONT POINT-SIZE=\"10\">wires drawn through the routing systems "
            f"{html.escape(', '.join(sorted(folded)))}; blue: into the plant; every port: "
            "diagram.svg</FONT>"
            if folded else "")
    lines = ["digraph overview {", "rankdir=LR;", "nodesep=0.2;", "ranksep=0.8;",
             f'label=<<B>{html.escape(title)}</B>{note}>; labelloc=t; fontname="Helvetica";',
             'node [shape=plaintext, fontname="Helvetica", fontsize=10];',
             'edge [arrowsize=0.6, color="#444444"];']

    def cell(node, port):
        if port is None:
            return '<TD BORDER="0"></TD>'
        align = "LEFT" if port.startswith("u") else "RIGHT"
        return (f'<TD PORT="{port}" BORDER="1" ALIGN="{align}">'
                f"{html.escape(nodes[node][2].get(port, port))}</TD>")
    for node, (kind, name, ports) in nodes.items():
        if node in loggers:
            continue
        ins, outs = ([p for p in sorted(ports, key=lambda p: int(p[1:]))
                      if p[0] == side and (node, p) in used] for side in "uy")
        colour = "#dbe8f6" if kind == "MultibodyPlant" else "#f2f2f2"
        rows = [f'<TR><TD COLSPAN="2" BORDER="1" BGCOLOR="{colour}"><B>'
                f"{html.escape(kind.split('.')[-1])}</B><BR/>{html.escape(name)}</TD></TR>"]
        rows += ["<TR>" + cell(node, ins[k] if k < len(ins) else None)
                 + cell(node, outs[k] if k < len(outs) else None) + "</TR>"
                 for k in range(max(len(ins), len(outs)))]
        lines.append(f'{node} [label=<<TABLE BORDER="0" CELLSPACING="0" CELLPADDING="3">'
                     + "".join(rows) + "</TABLE>>];")
    if loggers:
        rows = "".join(f'<TR><TD PORT="{n}" BORDER="1" ALIGN="LEFT">'
                       f"{html.escape(nodes[n][1])}</TD></TR>" for n in loggers)
        lines.append('loggers [label=<<TABLE BORDER="0" CELLSPACING="0" CELLPADDING="3">'
                     '<TR><TD BORDER="1" BGCOLOR="#fff4d6"><B>VectorLogSink</B><BR/>the logs'
                     f"</TD></TR>{rows}</TABLE>>];")
    if any(d == "meshcat_in" for _, _, d, _ in edges):
        lines.append('meshcat_in [label="Meshcat", shape=ellipse, color=magenta];')
    for src, sp, dst, dp in edges:
        tail = f"{src}:{sp}:e" if sp else src
        head = f"loggers:{dst}:w" if dst in loggers else f"{dst}:{dp}:w" if dp else dst
        style = (" [style=dashed, color=magenta]" if dst == "meshcat_in" else
                 ' [color="#1f5fbf"]' if nodes.get(dst, ("",))[0] == "MultibodyPlant" else "")
        lines.append(f"{tail} -> {head}{style};")
    return "\n".join(lines + ["}"]) + "\n"


def write_diagram_overview_svg(dot_text, path):
    """``diagram_overview_dot`` of Drake's Graphviz text, drawn as SVG."""
    write_diagram_svg(diagram_overview_dot(dot_text), path)
    Path(path).with_suffix(".dot").unlink(missing_ok=True)
