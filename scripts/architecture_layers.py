#!/usr/bin/env python3
"""Labels each node of the library graph with its layer folder (docs/architecture.md "Folders")
and fills it with that layer's colour, so that the picture shows the folders as well as the
link edges. (Boxes per folder, graphviz clusters, were tried: they pulled the layout apart and
overlapped.)

Usage: architecture_layers.py SOURCE_ROOT LINK_GRAPH.txt IN.dot OUT.dot
LINK_GRAPH.txt is what cmake/LdoemLinkGraph.cmake writes at configure time (target|type|dir|...);
IN.dot is CMake's --graphviz output. A node whose target has no folder stays outside any box.
"""
import os
import re
import sys


def layer_of(relative_dir):
    """The layer a target's folder belongs to: emulator/ one level down, the rest at the top
    (base, protocol, capture, driver, tools, python)."""
    parts = relative_dir.split(os.sep)
    if parts[0] == "emulator" and len(parts) > 1:
        return "/".join(parts[:2])
    return parts[0]


# Pale fills, so that the black labels and edges stay readable.
PALETTE = ["#cfe2ff", "#f8d7da", "#d1e7dd", "#fff3cd", "#e2d9f3", "#cff4fc", "#fde2c8", "#e9ecef",
           "#f7d6e6", "#d3f0c2", "#c9e4de", "#f0e1c6", "#dcdcf5", "#ffd8b1"]


def main(root, link_graph, dot_in, dot_out):
    folder = {}
    with open(link_graph, encoding="utf-8") as lines:
        for line in lines:
            fields = line.rstrip("\n").split("|")
            if len(fields) > 2:
                folder[fields[0]] = os.path.relpath(fields[2], root)
    text = open(dot_in, encoding="utf-8").read()
    drawn = re.findall(r'\[ label = "([^"]+)"', text)
    layers = sorted({layer_of(folder[label]) for label in drawn if label in folder})
    colour = {layer: PALETTE[i % len(PALETTE)] for i, layer in enumerate(layers)}

    def with_layer(match):
        label, rest = match.group(1), match.group(2)
        if label not in folder:
            return match.group(0)
        layer = layer_of(folder[label])
        return (f'[ label = "{label}\\n{layer}/"{rest}, style = filled, fillcolor = "{colour[layer]}" ]')

    text = re.sub(r'\[ label = "([^"]+)"([^\]]*) \]', with_layer, text)
    with open(dot_out, "w", encoding="utf-8") as out:
        out.write(text)


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    main(*sys.argv[1:])
