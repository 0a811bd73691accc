#!/usr/bin/env python3
"""Checks the architecture of include/qrm: no loose facility headers beside the layer folders
(only the umbrellas and version.hpp), and no #include from a layer to one above it.

Layers, lowest first: support, circuit, backends, estimation, noise, resources, walk, render. io stands apart: it may
use support only, and only render (and the top umbrella) may use io. Usage: check_layers.py INCLUDE_DIR
"""
import os
import re
import sys

ORDER = ["support", "circuit", "backends", "estimation", "noise", "resources", "walk", "render"]
ALLOWED = {name: set(ORDER[: i + 1]) for i, name in enumerate(ORDER)}
ALLOWED["io"] = {"support", "io"}
ALLOWED["render"] |= {"io"}
TOP_LEVEL = {name + ".hpp" for name in ALLOWED} | {"qrm.hpp", "version.hpp"}


def main(include_dir):
    root = os.path.join(include_dir, "qrm")
    errors = []
    for entry in sorted(os.listdir(root)):
        path = os.path.join(root, entry)
        if os.path.isdir(path):
            if entry not in ALLOWED:
                errors.append(f"qrm/{entry}/: not a known layer folder ({', '.join(ALLOWED)})")
        elif entry not in TOP_LEVEL:
            errors.append(f"qrm/{entry}: a loose header beside the layer folders (move it into a layer)")
    include = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
    for layer in ALLOWED:
        layer_root = os.path.join(root, layer)
        umbrella = os.path.join(root, layer + ".hpp")
        files = [umbrella] if os.path.exists(umbrella) else []
        for dirpath, _, names in os.walk(layer_root):
            files += [os.path.join(dirpath, n) for n in names if n.endswith(".hpp")]
        for f in files:
            text = open(f, encoding="utf-8").read()
            for m in include.finditer(text):
                target = os.path.normpath(os.path.join(os.path.dirname(f), m.group(1)))
                rel = os.path.relpath(target, root)
                if rel.startswith(".."):
                    errors.append(f"{os.path.relpath(f, include_dir)}: includes {m.group(1)}, outside qrm/")
                    continue
                if rel == "version.hpp":
                    continue
                target_layer = rel.split(os.sep)[0].removesuffix(".hpp")
                if target_layer not in ALLOWED[layer]:
                    errors.append(f"{os.path.relpath(f, include_dir)}: layer '{layer}' includes {rel} "
                                  f"from the higher layer '{target_layer}'")
    for e in errors:
        print(e)
    print(f"{len(errors)} layering errors")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
