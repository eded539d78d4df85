#!/usr/bin/env python3
"""Fails when a target includes a header of a library it does not link (issue 22, item 5).

    scripts/check-include-edges.py LINK_GRAPH [SOURCE_ROOT]

LINK_GRAPH is the file cmake/LdoemLinkGraph.cmake writes at configure time
(build/<preset>/ldoem-link-graph.txt). A header `ldoem/<part>/...` belongs to the library whose
folder holds include/ldoem/<part>/. A target may include it when that library is the target itself
or comes with a target it links (PUBLIC and INTERFACE links carry headers on; a static library's
private dependency does not). Checked: each target's sources, and a library's own headers
(include/ and src/). Also fails when a target's own include folders (target_include_directories)
reach into the folder of a library it does not link: that is how a header used to arrive without
its library, and the architecture graph, drawn from the links, could not show the edge.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]ldoem/([A-Za-z0-9_]+)/[^">]+[">]')
HEADER_SUFFIXES = (".hpp", ".h")


def read_graph(path):
    targets = {}
    with open(path, encoding="utf-8") as graph:
        for line in graph:
            fields = line.rstrip("\n").split("|")
            if len(fields) != 7:
                continue
            name, kind, folder, sources, links, interface_links, includes = fields
            split = lambda text: [item for item in text.split(";") if item]
            targets[name] = {"kind": kind, "folder": folder, "sources": split(sources),
                             "links": split(links), "interface_links": split(interface_links),
                             "includes": split(includes)}
    return targets


def owners_of_parts(targets):
    owners = {}
    for name, target in targets.items():
        if not target["kind"].endswith("LIBRARY"):
            continue
        include = os.path.join(target["folder"], "include", "ldoem")
        if os.path.isdir(include):
            for part in os.listdir(include):
                if os.path.isdir(os.path.join(include, part)):
                    owners.setdefault(part, set()).add(name)
    return owners


def reachable(targets, name):
    """The target and every target whose headers come with it."""
    seen = {name}
    pending = [entry for entry in targets[name]["links"] + targets[name]["interface_links"]]
    while pending:
        entry = pending.pop()
        if entry.startswith("LINK_ONLY:") or entry in seen or entry not in targets:
            continue
        seen.add(entry)
        pending.extend(targets[entry]["interface_links"])
    return seen


def included_parts(path):
    parts = []
    try:
        with open(path, encoding="utf-8", errors="replace") as source:
            for number, line in enumerate(source, 1):
                match = INCLUDE.match(line)
                if match:
                    parts.append((number, match.group(1)))
    except OSError:
        pass
    return parts


def files_below(folder):
    for directory, _, names in os.walk(folder):
        for name in sorted(names):
            yield os.path.join(directory, name)


def include_edge_problems(targets, root):
    owners = owners_of_parts(targets)
    # A library's own headers are checked against every library of its folder that owns the part
    # (driver/hub holds the hub and its client): a header does not say which of them uses it.
    headers = {}  # path -> allowed targets
    checks = []   # (path, who, allowed targets)
    for name, target in targets.items():
        allowed = reachable(targets, name)
        for source in target["sources"]:
            path = source if os.path.isabs(source) else os.path.join(target["folder"], source)
            if path.startswith(root + os.sep):
                checks.append((path, name, allowed))
        if target["kind"].endswith("LIBRARY"):
            for sub in ("include", "src"):
                for path in files_below(os.path.join(target["folder"], sub)):
                    if path.endswith(HEADER_SUFFIXES):
                        headers.setdefault(path, set()).update(allowed)
    checks.extend((path, "the library of " + os.path.relpath(os.path.dirname(path), root), allowed) for path, allowed in headers.items())
    problems = []
    for path, who, allowed in checks:
        for number, part in included_parts(path):
            libraries = owners.get(part)
            if libraries and not libraries & allowed:
                problems.append(f"{os.path.relpath(path, root)}:{number}: {who} includes ldoem/{part}/ "
                                f"but does not link {' or '.join(sorted(libraries))}")
    return sorted(set(problems))


def inside(path, folder):
    return path == folder or path.startswith(folder + os.sep)


def include_folder_problems(targets, root):
    library_folders = {}
    for name, target in targets.items():
        if target["kind"].endswith("LIBRARY"):
            library_folders.setdefault(target["folder"], set()).add(name)
    problems = []
    for name, target in targets.items():
        allowed = reachable(targets, name)
        for include in target["includes"]:
            include = os.path.normpath(include)
            if not inside(include, root) or inside(include, target["folder"]):
                continue
            for folder, libraries in library_folders.items():
                if inside(include, folder) and not libraries & allowed:
                    problems.append(f"{name}: its include folder {os.path.relpath(include, root)} lies in the "
                                    f"folder of {' or '.join(sorted(libraries))}, which it does not link")
    return problems


def main(argv):
    if len(argv) not in (2, 3):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    root = os.path.realpath(argv[2] if len(argv) == 3 else os.path.join(os.path.dirname(argv[0]), ".."))
    targets = read_graph(argv[1])
    problems = include_edge_problems(targets, root) + include_folder_problems(targets, root)
    for problem in problems:
        print("check-include-edges: " + problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
