#!/usr/bin/env python3
"""docs/architecture.md's request trace against the code (issue 22 item 11).

Every file the trace's tables name must exist, and every function or method a row names must be
defined or called in one of the files of that row; every other code name in a row (a type, a
constant, a scene key) must occur somewhere in the sources. A file moved or a function renamed
without the trace following it fails here, not in a newcomer's hands.

Usage: architecture_trace.py SOURCE_DIR
"""
import pathlib
import re
import sys

SOURCE_SUFFIXES = {".cpp", ".hpp", ".h"}
SKIP_DIRS = {".git", "build", "out"}


def source_files(root):
    for path in root.rglob("*"):
        if path.suffix in SOURCE_SUFFIXES and not SKIP_DIRS.intersection(path.relative_to(root).parts):
            yield path


def resolve(root, by_name, span):
    """The files a span such as `emulator/host/io/src/tcp.cpp`, `stage_*.cpp` or `sim_clock.cpp` names."""
    if "/" in span:
        return sorted(root.glob(span))
    return sorted(p for name, paths in by_name.items() if pathlib.PurePath(name).match(span) for p in paths)


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    doc = root / "docs" / "architecture.md"
    text = doc.read_text()
    start = text.index("## One GET_PROFILE")
    rows = [line for line in text[start:].splitlines() if re.match(r"\|\s*\d+\s*\|", line)]
    by_name = {}
    for path in source_files(root):
        by_name.setdefault(path.name, []).append(path)
    all_sources = None
    failures = []
    checked = 0
    for row in rows:
        cells = [cell.strip() for cell in row.strip().strip("|").split("|")]
        step = cells[0]
        spans = re.findall(r"`([^`]+)`", " ".join(cells[1:]))
        files, names = [], []
        for span in spans:
            for part in (p.strip() for p in span.split(",")):
                if pathlib.PurePath(part).suffix in SOURCE_SUFFIXES:
                    found = resolve(root, by_name, part)
                    checked += 1
                    if not found:
                        failures.append(f"step {step}: file `{part}` does not exist")
                    files.extend(found)
                else:
                    names.append(part)
        contents = "\n".join(f.read_text(errors="replace") for f in files)
        for name in names:
            call = re.match(r"^(?:[A-Za-z_]\w*::)*([a-z_]\w*)\s*\(", name) or \
                re.match(r"^(?:[A-Za-z_]\w*::)+([a-z_]\w*)$", name)
            if call:
                checked += 1
                if not re.search(r"\b" + re.escape(call.group(1)) + r"\b", contents):
                    failures.append(f"step {step}: `{name}` is in none of the row's files "
                                    f"({', '.join(str(f.relative_to(root)) for f in files) or 'none'})")
                continue
            identifier = re.match(r"^(?:[A-Za-z_]\w*::)*([A-Za-z_]\w*)$", name)
            if not identifier:
                continue  # a value such as 0x0301 or a quoted text
            checked += 1
            if all_sources is None:
                all_sources = "\n".join(p.read_text(errors="replace") for paths in by_name.values() for p in paths)
            if not re.search(r"\b" + re.escape(identifier.group(1)) + r"\b", all_sources):
                failures.append(f"step {step}: `{name}` occurs in no source file")
    if len(rows) < 10:
        failures.append(f"only {len(rows)} trace rows found: has the table's format changed?")
    for failure in failures:
        print("FAIL docs/architecture.md", failure)
    print(f"architecture trace: {len(rows)} steps, {checked} names checked, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
