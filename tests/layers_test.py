#!/usr/bin/env python3
"""The layers of docs/architecture.md, checked on every #include.

Reads every C++ source and header under the repository's folders and fails (exit 1, one line per
include: file:line: what points where) on an #include that points up the layer order:

- between top-level folders (LAYERS below: a folder may include its own files and those of lower
  layers; folders on the same layer may not include each other);
- between the sub-folders of accel/ (ACCEL_LAYERS, the same rule), and on a file directly in accel/
  or in a sub-folder the order does not name (a new folder must be placed in the order first).

With strict layers an upward include is the only way to close a circle, so 0 upward includes
means 0 circles. `--self-test` runs the check on a small tree it makes, with one upward include of
each kind and one same-layer include, and fails unless each is caught and the clean tree passes.
"""
import argparse
import pathlib
import re
import sys
import tempfile

# Top-level folders, lowest first. include/ holds the public headers (<arbor/...>), which include
# nothing of arbor's own; the test suite may use everything.
LAYERS = {
    "include": 0, "simd": 0,
    "accel": 1,
    "engine": 2, "mpi": 2,
    "api": 3, "stress": 3, "view": 3,
    "apps": 4,
    "perf": 5, "python": 5, "fuzz": 5,
    "tests": 6,
}
# accel/'s sub-folders, lowest first (accel/CMakeLists.txt and docs/architecture.md say what each holds).
ACCEL_LAYERS = {
    "util": 0,
    "core": 1,
    "bvh": 2,
    "lbvh": 3,
    "wide": 4, "kdtree": 4,
    "interface": 5,
    "structures": 6,
    "dispatch": 7,
    "factory": 8,
    "select": 9, "instances": 9,
}
SOURCE = re.compile(r"\.(h|hpp|cpp|cc|in)$")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]')


def target_folder(path: str):
    """The top-level folder an include path names (arbor/x.h is include/arbor/x.h), or None."""
    head = path.split("/", 1)[0]
    if head == "arbor":
        return "include"
    return head if head in LAYERS and "/" in path else None


def check(root: pathlib.Path) -> list:
    problems = []
    for top in sorted(LAYERS):
        base = root / top
        if not base.is_dir():
            continue
        for f in sorted(base.rglob("*")):
            if not f.is_file() or not SOURCE.search(f.name):
                continue
            rel = f.relative_to(root).as_posix()
            parts = rel.split("/")
            sub = parts[1] if top == "accel" and len(parts) > 2 else None
            if top == "accel" and sub is None and f.name != "CMakeLists.txt":
                problems.append(f"{rel}: a file directly in accel/ (each belongs to a layer folder)")
            if top == "accel" and sub is not None and sub not in ACCEL_LAYERS:
                problems.append(f"{rel}: accel/{sub}/ is not in the layer order (tests/layers_test.py, docs/architecture.md)")
            for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                inc = m.group(1)
                to = target_folder(inc)
                if to is None:
                    continue
                if to != top and LAYERS[to] >= LAYERS[top]:
                    how = "up" if LAYERS[to] > LAYERS[top] else "sideways (same layer)"
                    problems.append(f"{rel}:{n}: includes {inc}: {top}/ -> {to}/ points {how}")
                if top == "accel" and to == "accel" and sub in ACCEL_LAYERS:
                    isub = inc.split("/")[1] if inc.count("/") >= 2 else None
                    if isub is None or isub not in ACCEL_LAYERS:
                        problems.append(f"{rel}:{n}: includes {inc}: not in a layer folder of accel/")
                    elif isub != sub and ACCEL_LAYERS[isub] >= ACCEL_LAYERS[sub]:
                        how = "up" if ACCEL_LAYERS[isub] > ACCEL_LAYERS[sub] else "sideways (same layer)"
                        problems.append(f"{rel}:{n}: includes {inc}: accel/{sub}/ -> accel/{isub}/ points {how}")
    return problems


def self_test() -> int:
    with tempfile.TemporaryDirectory() as d:
        root = pathlib.Path(d)

        def put(path, text):
            p = root / path
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_text(text)

        put("simd/a.h", "#pragma once\n")
        put("accel/core/ray.h", '#include "simd/a.h"\n#include "accel/util/t.h"\n')
        put("accel/util/t.h", "#pragma once\n")
        put("accel/structures/s.h", '#include "accel/core/ray.h"\n')
        put("engine/e.h", '#include "accel/structures/s.h"\n')
        if check(root):
            print("self-test: the clean tree was refused:", check(root))
            return 1
        bad = {
            "accel/core/up.h": '#include "accel/structures/s.h"\n',       # accel layer up
            "accel/wide/w.h": '#include "accel/kdtree/k.h"\n',            # same accel layer
            "accel/kdtree/k.h": "#pragma once\n",
            "accel/newdir/n.h": "#pragma once\n",                          # folder not in the order
            "accel/top.h": "#pragma once\n",                               # file directly in accel/
            "simd/b.h": '#include "engine/e.h"\n',                         # top-level up
            "view/v.h": '#include "stress/x.h"\n',                         # same top-level layer
        }
        for path, text in bad.items():
            put(path, text)
        found = "\n".join(check(root))
        expect = ["accel/core/up.h:1", "accel/wide/w.h:1", "accel/newdir/n.h", "accel/top.h", "simd/b.h:1", "view/v.h:1"]
        missed = [e for e in expect if e not in found]
        if missed:
            print("self-test: not caught:", ", ".join(missed))
            print(found)
            return 1
    print("layers self-test: 6 of 6 planted violations caught, the clean tree passes")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=str(pathlib.Path(__file__).resolve().parents[1]))
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    problems = check(pathlib.Path(a.root))
    for p in problems:
        print(p)
    if problems:
        print(f"layers: {len(problems)} include(s) against the layer order (docs/architecture.md)")
        return 1
    print("layers: every #include points down the layer order")
    return 0


if __name__ == "__main__":
    sys.exit(main())
