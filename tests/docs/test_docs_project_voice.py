"""The documentation speaks of the project as it is: no doc (docs/**/*.md, README.md,
CHANGELOG.md) and no public header (include/) names an issue number or a development session;
that history is in git.

A "session" of another kind (an MPI session, a pytest fixture's scope, a ParaView session) is
fine: a development session is recognised by its number ("session 11", "sessions 7–9") or by
the words that place it in time ("this session", "the previous session", "a development
session"), an issue by its number ("issue 28", "issues 7 and 11", "#28").
"""
import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))

# Searched in the whole text, so that a mention wrapped over two lines is found too.
PATTERNS = (
    re.compile(r"\bissues?\s*#?\s*\d+", re.IGNORECASE),
    re.compile(r"(?<![\w&#])#\d+\b"),
    re.compile(r"\bsessions?\s*#?\s*\d+", re.IGNORECASE),
    re.compile(r"\b(?:this|that|same|previous|earlier|later|next|last|development|coding|work|"
               r"working)\s+sessions?\b", re.IGNORECASE),
)


def checked_files():
    """Every file the rule covers: the docs' Markdown, the README, the changelog, the headers."""
    files = sorted((ROOT / "docs").rglob("*.md"))
    files += [ROOT / "README.md", ROOT / "CHANGELOG.md"]
    files += sorted(p for p in (ROOT / "include").rglob("*") if p.is_file())
    return files


def history_mentions(text):
    """(line number, line) of each place in TEXT that names an issue or a development session."""
    found = set()
    for pattern in PATTERNS:
        for match in pattern.finditer(text):
            found.add(text.count("\n", 0, match.start()) + 1)
    lines = text.splitlines()
    return [(n, lines[n - 1].strip()) for n in sorted(found)]


@pytest.mark.parametrize("text", [
    "Measured in issue 28.",
    "## Issue 11, session 5: noise",
    "as issue #7 asked",
    "the runs of issues 7 and 11",
    "see #28 for the discussion",
    "the figures of session 11",
    "Same machine as sessions 7–9.",
    "not re-measured this session",
    "(the previous session's binary)",
    "written in a development session",
    "what the issue asked (issue\n11, item 4)",
])
def test_a_mention_of_an_issue_or_a_session_is_found(text):
    assert history_mentions(text), text


@pytest.mark.parametrize("text", [
    "Runs every index on the session's ranks (MpiSession).",
    "const MpiSession session;  // not started by a launcher: one rank",
    "@pytest.fixture(scope=\"session\")",
    "each `pvbatch` run that reads a file 5–9 s",
    "soft tissue, a 3 mm error",
    "#include \"moreau/common/error.h\"",
    "&#8211; an HTML entity",
    "thesis 9.2, Fig. 16",
])
def test_other_sessions_and_numbers_are_not_taken_for_history(text):
    assert not history_mentions(text), text


def test_the_rule_covers_the_docs_the_readme_the_changelog_and_the_headers():
    files = checked_files()
    names = {p.relative_to(ROOT).as_posix() for p in files}
    assert {"README.md", "CHANGELOG.md", "docs/ARCHITECTURE.md", "docs/benchmarks.md"} <= names
    assert all(p.is_file() for p in files), [p for p in files if not p.is_file()]
    assert sum(n.startswith("include/moreau/") and n.endswith(".h") for n in names) >= 20


def test_no_doc_or_public_header_names_an_issue_or_a_development_session():
    hits = []
    for path in checked_files():
        for line_number, line in history_mentions(path.read_text(encoding="utf-8")):
            hits.append(f"{path.relative_to(ROOT)}:{line_number}: {line}")
    assert not hits, "history belongs in git; say what the project is or does:\n" + "\n".join(hits)
