"""The size limits of the sources: no file of the library, the tool or the bindings over 500
lines, and no function over 80 lines (its body, from the line of its opening brace to its closing
one). Functions are found as clang-format writes them: a definition ends with a line that is
`}` alone at the indentation of a namespace member (0) or a class member (2); its opening brace
is found by counting braces backwards, outside comments, strings and characters."""
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
FOLDERS = ("src", "include", "apps", "python/src")
MAX_FILE_LINES = 500
MAX_FUNCTION_LINES = 80


def sources():
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix in (".h", ".cpp"):
                yield path


def code_only(text):
    """The text with comments, string and character literals blanked (newlines kept)."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|R"([^(]*)\(.*?\)\1"|"(?:\\.|[^"\\\n])*"|'
                         r"'(?:\\.|[^'\\\n])*'", re.S)
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def long_functions(text, limit=MAX_FUNCTION_LINES):
    """(first line, lines) of every function body longer than `limit` lines."""
    lines = code_only(text).split("\n")
    out = []
    for end, line in enumerate(lines):
        if line not in ("}", "  }"):
            continue
        depth = 0
        for start in range(end, -1, -1):
            depth += lines[start].count("}") - lines[start].count("{")
            if depth == 0:
                break
        if end - start > limit:
            out.append((start + 1, end - start))
    return out


def test_no_source_file_is_over_500_lines():
    long = [f"{p.relative_to(ROOT)}: {n}" for p in sources()
            if (n := len(p.read_text().splitlines())) > MAX_FILE_LINES]
    assert not long, long


def test_no_function_is_over_80_lines():
    long = [f"{p.relative_to(ROOT)}:{line}: {n} lines" for p in sources()
            for line, n in long_functions(p.read_text())]
    assert not long, long


def test_the_function_finder_sees_a_long_function_and_skips_comments_and_strings():
    body = "\n".join(["  x += 1;"] * 81)
    text = f"int F() {{\n  // }} not a brace\n  const char* s = \"{{\";\n{body}\n}}\n"
    assert long_functions(text) == [(1, 84)]
    assert long_functions(text, limit=100) == []
    member = f"struct S {{\n  void G() {{\n{body}\n  }}\n}};\n"
    assert long_functions(member) == [(2, 82)]
