"""The Diagram's pictures: Drake's Graphviz drawing as SVG (``diagram_svg``; written by
``results.files.write_diagram_svg``) and a readable overview of it (``diagram_overview_dot``)."""

import errno
import shutil
import subprocess


def diagram_svg(dot_text):
    """Graphviz ``dot_text`` drawn as SVG text."""
    dot = shutil.which("dot")
    if dot is None:
        # The machine lacks a program: an OS error, one line through the commands' error path.
        raise FileNotFoundError(errno.ENOENT, "Graphviz's program is not installed; run "
                                "tools/setup.sh (or install the 'graphviz' package) to draw "
                                "the diagram", "dot")
    return subprocess.run([dot, "-Tsvg"], input=dot_text, capture_output=True, text=True,
                          check=True, timeout=120).stdout


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

