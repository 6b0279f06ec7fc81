#!/usr/bin/env python3
"""The layering check: every #include points down, never up.

The layers, lowest first: fixed/ (numbers), core/ (the simulator), replay/
(formats, sessions, the C API), tools/ (the command line, the bench, the
cross check, fuzzing, the viewer). A file may include its own layer and the
ones below. tests/X/ sits on the layer of X (tests/fixed/ links nothing
above fixed/); a shared test header at the top of tests/ takes the highest
layer it includes. Nothing outside tests/ includes tests/.

  tools/check_layers.py [ROOT]   prints each upward include; exit 1 if any
  tools/check_layers.py --planted  the check on a planted tree: it must name
                                   its two upward includes and pass the rest
"""
import os
import re
import sys
import tempfile

LAYERS = ["fixed", "core", "replay", "tools"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)
SOURCES = (".h", ".hpp", ".cpp", ".c")


def own_layer(path):
    """The layer a file sits on, or None for a shared test header."""
    parts = path.split("/")
    if parts[0] == "tests":
        return LAYERS.index(parts[1]) if len(parts) > 2 and parts[1] in LAYERS else None
    return LAYERS.index(parts[0])


def check(root):
    includes = {}
    for top in LAYERS + ["tests"]:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in names:
                if name.endswith(SOURCES):
                    path = os.path.relpath(os.path.join(folder, name), root)
                    if path.startswith("tests/consumer/"):
                        continue  # builds against the installed package
                    with open(os.path.join(root, path), encoding="utf-8") as f:
                        found = INCLUDE.findall(f.read())
                    includes[path] = [p for p in found if p.split("/")[0] in LAYERS + ["tests"]]

    memo = {}

    def layer(path, seen=()):
        """A file's layer; a shared test header's is its highest include's."""
        if path in memo:
            return memo[path]
        fixed_layer = own_layer(path)
        if fixed_layer is None:
            fixed_layer = max((layer(p, seen + (path,)) for p in includes.get(path, []) if p not in seen), default=0)
        memo[path] = fixed_layer
        return fixed_layer

    problems = []
    for path in sorted(includes):
        for target in includes[path]:
            if target.startswith("tests/") and not path.startswith("tests/"):
                problems.append(f"{path}: includes {target}: only tests include tests/")
            elif target in includes or os.path.exists(os.path.join(root, target)):
                if layer(target) > layer(path):
                    problems.append(f"{path}: includes {target}: {LAYERS[layer(target)]}/ is above "
                                    f"{LAYERS[layer(path)]}/")
    return len(includes), problems


def planted():
    """A tree with two upward includes (core/ into fixed/, tools/ into a
    shared test header a tests/fixed file includes) among allowed ones."""
    files = {
        "fixed/a.h": '#include "fixed/b.h"\n#include "core/c.h"\n',
        "fixed/b.h": "",
        "core/c.h": '#include "fixed/b.h"\n',
        "tools/d.h": '#include "core/c.h"\n',
        "tests/shared.h": '#include "tools/d.h"\n',
        "tests/fixed/t.cpp": '#include "tests/shared.h"\n#include "fixed/a.h"\n',
        "tests/tools/u.cpp": '#include "tests/shared.h"\n',
    }
    with tempfile.TemporaryDirectory() as root:
        for path, text in files.items():
            os.makedirs(os.path.join(root, os.path.dirname(path)), exist_ok=True)
            with open(os.path.join(root, path), "w", encoding="utf-8") as f:
                f.write(text)
        _, problems = check(root)
    expected = ["fixed/a.h: includes core/c.h: core/ is above fixed/",
                "tests/fixed/t.cpp: includes tests/shared.h: tools/ is above fixed/"]
    for problem in problems:
        print(problem)
    ok = problems == expected
    print(f"check_layers --planted: {'named both' if ok else 'WRONG, expected: ' + '; '.join(expected)}")
    return 0 if ok else 1


def main():
    if sys.argv[1:] == ["--planted"]:
        return planted()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    count, problems = check(root)
    for problem in problems:
        print(problem)
    print(f"check_layers: {count} files, {len(problems)} upward includes")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
