"""docs/python.md lists every bound name; the stubs cover every bound name."""
import moreau
from conftest import ROOT

PARTS = ("particles", "pbd", "control", "mocap")


def public_names(part):
    return {n for n in vars(getattr(moreau, part)) if not n.startswith("_")}


def test_docs_list_every_bound_name():
    text = (ROOT / "docs/python.md").read_text()
    for part in PARTS:
        section = text.split(f"### moreau.{part}\n", 1)[1].split("###", 1)[0]
        missing = {n for n in public_names(part) if f"`{n}`" not in section}
        assert not missing, (part, missing)
    assert "`NumericalError`" in text


def test_stubs_cover_every_bound_name():
    for part in PARTS:
        stub = (ROOT / "python/moreau" / f"{part}.pyi").read_text()
        missing = {n for n in public_names(part)
                   if f"class {n}" not in stub and f"def {n}(" not in stub}
        assert not missing, (part, missing)


def test_every_example_runs():
    text = (ROOT / "docs/python.md").read_text()
    for block in text.split("```python\n")[1:]:
        example = block.split("```", 1)[0]
        exec(compile(example, "docs/python.md", "exec"), {})
