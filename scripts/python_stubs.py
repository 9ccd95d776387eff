#!/usr/bin/env python3
"""Writes the type stubs python/moreau/<part>.pyi from the built module's pybind11 signatures,
and (with --markdown) prints the list of bound names that docs/python.md carries.

    PYTHONPATH=build/release/python /usr/bin/python3 scripts/python_stubs.py [--markdown]
"""
import ast
import pathlib
import re
import sys

import moreau

PARTS = ("particles", "pbd", "control", "mocap")
ROOT = pathlib.Path(__file__).resolve().parents[1]


def clean(signature, part):
    """A pybind11 signature as stub syntax: own types unqualified, others as part.Name."""
    s = re.sub(rf"moreau\._moreau\.{part}\.", "", signature)
    s = re.sub(r"moreau\._moreau\.(\w+)\.", r"\1.", s)
    s = re.sub(r"numpy\.ndarray\[[^\[\]]*(\[[^\]]*\])?[^\[\]]*\]", "numpy.ndarray", s)
    s = re.sub(r"(\w)\[\d+\]", r"\1", s)  # std::array<double, 3> reads List[float[3]]
    s = re.sub(r"moreau::(?:\w+::)*(\w+)", r"\1", s)  # a type bound after its first use
    return s.replace("os.PathLike", "os.PathLike[str]")


def signature(obj, name):
    doc = (obj.__doc__ or "").strip().splitlines()
    first = doc[0] if doc else f"{name}(*args, **kwargs) -> object"
    summary = next((line.strip() for line in doc[1:] if line.strip()), "")
    return first, summary


def members(cls):
    for name, value in vars(cls).items():
        if name.startswith("_") and name not in ("__init__", "__call__"):
            continue
        yield name, value


def stub(part):
    module = getattr(moreau, part)
    lines = ['"""Type stubs of moreau.%s (scripts/python_stubs.py writes them)."""' % part,
             "import os", "from typing import *", "", "import numpy",
             "from moreau import " + ", ".join(p for p in PARTS if p != part), ""]
    names = []
    for name, value in sorted(vars(module).items()):
        if name.startswith("_"):
            continue
        if isinstance(value, type):
            bases = [b.__name__ for b in value.__bases__ if b.__module__.startswith("moreau")]
            lines.append(f"class {name}{'(' + ', '.join(bases) + ')' if bases else ''}:")
            names.append((name, [m for m, _ in members(value) if not m.startswith("_")]))
            for member, attribute in members(value):
                if isinstance(attribute, property):
                    text = clean(signature(attribute.fget, member)[0], part)
                    kind = text.split("->")[-1].strip()
                    lines += ["    @property", f"    def {member}(self) -> {kind}: ..."]
                    if attribute.fset is not None:
                        lines += [f"    @{member}.setter",
                                  f"    def {member}(self, value: {kind}) -> None: ..."]
                else:
                    text = clean(signature(attribute, member)[0], part)
                    if text.startswith(member + "("):  # else: no constructor bound
                        lines.append(f"    def {text}: ...")
            lines.append("")
        elif callable(value):
            lines.append(f"def {clean(signature(value, name)[0], part)}: ...")
            names.append((name, None))
    text = "\n".join(lines) + "\n"
    ast.parse(text)
    return text, names


def main():
    for part in PARTS:
        text, names = stub(part)
        if "--markdown" in sys.argv:
            print(f"\n### moreau.{part}\n")
            for name, attributes in names:
                listed = ": " + ", ".join(f"`{a}`" for a in attributes) if attributes else ""
                print(f"- `{name}`{'()' if attributes is None else ''}{listed}")
        else:
            (ROOT / "python" / "moreau" / f"{part}.pyi").write_text(text)


if __name__ == "__main__":
    main()
