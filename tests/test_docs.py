"""The user documentation says what the code does: README and docs/ against the code itself.

README is short and its quick starts run as written; every docs page is reachable from
docs/index.md and every link resolves; no project history leaks into user pages; each command's
help lists the names its registry accepts; docs/commands.md is the command line's own help.

docs/commands.md is generated: ``python tests/test_docs.py`` rewrites it.
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md"))
USER_TEXTS = [README, *PAGES]

#: pages written on other branches of the same change; once present they are checked like the others
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
#: a word of 7-40 hex digits with at least one digit and one letter: a commit hash, not a number or a word
HASH = re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b")
ISSUE = re.compile(r"\bissues? #?\d+", re.IGNORECASE)


def _relative_links(path: Path) -> list[str]:
    """The link targets of a Markdown file that point into the repository (not to the web)."""
    return [t for t in LINK.findall(path.read_text()) if not re.match(r"[a-z]+:", t)]


def _anchors(path: Path) -> set[str]:
    """GitHub's anchors of a page's headings: lower case, punctuation dropped, spaces as hyphens."""
    heads = re.findall(r"^#+\s+(.*)$", path.read_text(), flags=re.MULTILINE)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in heads}


def test_readme_is_short():
    """README is for users: under 300 lines (everything else is in docs/)."""
    assert len(README.read_text().splitlines()) < 300


def test_every_docs_page_is_linked_from_the_index():
    """A page nobody links to is a page nobody reads: docs/index.md links every docs/*.md."""
    linked = {(DOCS / t.split("#")[0]).resolve() for t in _relative_links(DOCS / "index.md")}
    missing = [p.name for p in PAGES if p.name != "index.md" and p.resolve() not in linked]
    assert not missing


@pytest.mark.parametrize("path", USER_TEXTS, ids=lambda p: p.name)
def test_every_relative_link_resolves(path):
    """Every relative link of README and docs/ names a file that exists, and an anchor names a heading of it."""
    for target in _relative_links(path):
        file, _, anchor = target.partition("#")
        dest = (path.parent / file).resolve() if file else path
        assert dest.exists(), f"{path.name}: {target}"
        if anchor and dest.suffix == ".md":
            assert anchor in _anchors(dest), f"{path.name}: {target}"


@pytest.mark.parametrize("path", USER_TEXTS, ids=lambda p: p.name)
def test_no_project_history_in_user_pages(path):
    """No commit hashes and no issue numbers in README or docs/: a user has neither the history nor the tracker."""
    text = path.read_text()
    assert not HASH.findall(text)
    assert not ISSUE.findall(text)


def test_the_method_is_cited_by_its_reference_not_a_path():
    """README cites the paper by its title; it points at no folder a user does not have."""
    text = README.read_text()
    assert "../shared" not in text and "shared/paper" not in text
    assert "Seismic response of two adjacent non-symmetric multistory buildings" in text


# --------------------------------------------------------------------------- the quick starts
def _block_after(marker: str, language: str) -> str:
    """The fenced block of ``language`` that follows the HTML comment starting with ``marker`` in README."""
    text = README.read_text()
    assert f"<!-- {marker}" in text, marker
    after = text.split(f"<!-- {marker}", 1)[1]
    return after.split(f"```{language}\n", 1)[1].split("```", 1)[0]


def _quickstart() -> list[tuple[list[str], str | None, list[str]]]:
    """(arguments of pounding, file stdout goes to or None, files README says the line writes) per line."""
    steps = []
    for line in _block_after("quickstart:", "sh").strip().splitlines():
        command, _, comment = line.partition("#")
        words = shlex.split(command)
        assert words[0] == "pounding", line
        out = None
        if ">" in words:
            out = words[words.index(">") + 1]
            words = words[:words.index(">")]
        said = re.search(r"writes (.*?)(?::|$)", comment)
        files = [f.strip() for f in said.group(1).split(",")] if said else []
        steps.append((words[1:], out, files))
    return steps


def test_readme_quickstart_names_the_five_commands():
    """The quick start is template, check, run, plot, gap, in that order."""
    assert [args[0] for args, _, _ in _quickstart()] == ["template", "check", "run", "plot", "gap"]


@pytest.fixture(scope="module")
def quickstart_folder(tmp_path_factory):
    """An empty folder in which README's five commands were run, one by one, as README writes them."""
    folder = tmp_path_factory.mktemp("quickstart")
    for args, out, files in _quickstart():
        proc = subprocess.run([sys.executable, "-m", "pounding", *args], cwd=folder, capture_output=True, text=True)
        assert proc.returncode == 0, (args, proc.stderr)
        if out:
            (folder / out).write_text(proc.stdout)
        for f in files:
            assert (folder / f).is_file(), (args, f)
    return folder


def test_readme_quickstart_runs_and_writes_what_it_says(quickstart_folder):
    """Each line of the quick start exits 0 and writes the files its comment names (checked in the fixture)."""
    written = {f for _, out, files in _quickstart() for f in files + ([out] if out else [])}
    assert written and all((quickstart_folder / f).is_file() for f in written)


def test_summary_says_storey_shears_leave_out_damping(quickstart_folder):
    """summary.json says, per building, that storey shears are the elements' forces, without damping."""
    summary = json.loads((quickstart_folder / "run" / "summary.json").read_text())
    assert all(b["storey_shear_includes_damping_forces"] is False for b in summary["buildings"].values())


def test_outputs_page_defines_every_key_and_array_a_run_writes(quickstart_folder):
    """Every key of summary.json (top level and per building), every array of response.npz (per building
    as `B_...`) and every column of impacts.csv is named in docs/outputs.md."""
    import numpy as np

    page = (DOCS / "outputs.md").read_text()
    summary = json.loads((quickstart_folder / "run" / "summary.json").read_text())
    names = set(summary) | {k for b in summary["buildings"].values() for k in b}
    with np.load(quickstart_folder / "run" / "response.npz") as z:
        for key in z.files:
            building = next((b for b in summary["buildings"] if key.startswith(b + "_")), None)
            names.add("B_" + key[len(building) + 1:] if building else key)
    names |= set((quickstart_folder / "run" / "impacts.csv").read_text().splitlines()[0].split(","))
    assert not sorted(n for n in names if f"`{n}`" not in page)


def test_readme_python_quickstart_runs():
    """README's Python quick start runs as written, from the repository's root."""
    code = _block_after("python-quickstart:", "python")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


# --------------------------------------------------------------------------- what the texts say
def test_every_storey_force_in_outputs_says_damping_is_left_out():
    """Every table row of docs/outputs.md that defines a storey force (shear, base shear, moment) says damping is not in it."""
    rows = [r for r in (DOCS / "outputs.md").read_text().splitlines()
            if r.startswith("| `") and re.search(r"(storey|base|element)_shear|overturning", r.split("|")[1])]
    assert rows
    for row in rows:
        assert "damping" in row, row


def test_docs_name_every_builtin_integrator_and_contact_law():
    """docs/accuracy.md describes every integrator and contact law that ships with the code."""
    from pounding.framework.model.registry import CONTACT_LAWS, INTEGRATORS

    text = (DOCS / "accuracy.md").read_text()
    for name in INTEGRATORS.builtin_names() + CONTACT_LAWS.builtin_names():
        assert f"| `{name}`" in text, name


def test_texts_give_the_default_integrators_the_code_chooses():
    """README and docs/accuracy.md name the integrators integrator_choice picks; no integrator calls itself the default."""
    from pounding.framework.engine import integrator_choice
    from pounding.framework.model.registry import INTEGRATORS

    for path in (README, DOCS / "accuracy.md"):
        text = path.read_text()
        assert f"`{integrator_choice.ELASTIC}`" in text and f"`{integrator_choice.OTHERWISE}`" in text
    for name in INTEGRATORS.builtin_names():
        doc = INTEGRATORS.get(name).__doc__ or ""
        assert "default integrator" not in doc or name in (integrator_choice.ELASTIC, integrator_choice.OTHERWISE), name


def test_help_and_package_say_adjacent_buildings_not_two():
    """The tool runs pairs, rows and blocks: neither `pounding --help` nor the package docstring says "two"."""
    import pounding
    from pounding.cli import build_parser

    for text in (build_parser().description, pounding.__doc__.splitlines()[0]):
        assert "adjacent" in text and "two adjacent" not in text


def test_paper_example_readme_names_the_locator_its_scene_runs():
    """examples/paper/README says which impact locator the paper's scene runs (the law's default when unnamed)."""
    from pounding.framework.model.registry import CONTACT_LAWS
    from pounding.io.scene import load_scene

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    law = CONTACT_LAWS.get(scene.analysis.contact)(**scene.analysis.contact_params)
    row = next(r for r in (ROOT / "examples" / "paper" / "README.md").read_text().splitlines() if r.startswith("| contact"))
    assert f"`{law.locate}`" in row


# --------------------------------------------------------------------------- help against registries
def _subparsers():
    from pounding.cli import build_parser

    parser = build_parser()
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def _help(command: str, option: str) -> str:
    action = next(a for a in _subparsers()[command]._actions if option in a.option_strings)
    return " ".join(action.help.replace("%%", "%").split())


def _listed(help_text: str, candidates) -> set[str]:
    """The candidate names a help text lists, as whole words."""
    return {c for c in candidates if re.search(rf"(?<![\w-]){re.escape(c)}(?![\w-])", help_text)}


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_integrator_option_lists_the_registered_integrators(command):
    """`--integrator` lists every built-in integrator, and each name it lists is one the registry loads."""
    from pounding.framework.model.registry import INTEGRATORS

    text = _help(command, "--integrator")
    assert _listed(text, INTEGRATORS.builtin_names()) == set(INTEGRATORS.builtin_names())
    listed = re.search(r"\(([^)]*), or a plugin's name", text).group(1).split(", ")
    for name in listed:
        INTEGRATORS.get(name)


def test_template_element_option_lists_the_registered_elements():
    """`template --element` lists every built-in element type, each of which the registry loads."""
    from pounding.framework.model.registry import ELEMENTS

    text = _help("template", "--element")
    assert _listed(text, ELEMENTS.builtin_names()) == set(ELEMENTS.builtin_names())
    for name in ELEMENTS.builtin_names():
        ELEMENTS.get(name)


def test_silence_option_lists_the_plausibility_checks():
    """`--silence` lists every plausibility check by name (run and check)."""
    from pounding.framework.post.plausibility import NAMES

    for command in ("run", "check"):
        assert _listed(_help(command, "--silence"), NAMES) == set(NAMES)


def test_fragility_im_option_lists_what_the_study_accepts():
    """`fragility --im` lists pga and every spectral measure; each, and the NAME:T form its example gives, is accepted."""
    from pounding.framework.studies.fragility_inputs import INTENSITY_MEASURES, SPECTRAL, intensity_measure
    from pounding.io.scene import load_scene

    text = _help("fragility", "--im")
    names = list(INTENSITY_MEASURES) + list(SPECTRAL)
    assert _listed(text, names) == set(names)
    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    example = re.search(r"e\.g\. (\w+:[0-9.]+)", text).group(1)
    for name in [*names, example]:
        measure = intensity_measure(name, scene)
        assert measure.unit == "g" and callable(measure.fn)


@pytest.mark.parametrize("command", ["sweep", "fragility"])
def test_records_option_names_the_record_sets_the_code_loads(command):
    """`--records` names each record set pounding.io.records knows, and only those."""
    from pounding.io.records import P695_PREFIX, RECORD_SETS

    known = [P695_PREFIX + k for k in RECORD_SETS]
    text = _help(command, "--records")
    assert [m for m in re.findall(r"[\w-]+:[\w-]+", text)] == known


# --------------------------------------------------------------------------- docs/commands.md
INTRO = """# Commands

Every `pounding` command with its arguments, generated from the command line itself
(`pounding COMMAND --help` prints the same; `tests/test_docs.py` fails when this page differs
from it, and `python tests/test_docs.py` rewrites it). Exit codes: 0 success, 2 bad input (one
line on stderr naming the file, the key or option and what was expected), 1 an unexpected
failure or a failed check, 130 interrupted. Warnings go to stderr as `pounding: warning: ...`.

Lists (`LIST`) are comma-separated values, a range `a:b:n` (n values from a to b), or both.
What the commands write: [outputs.md](outputs.md); the studies explained: [studies.md](studies.md).
"""


def _usage(parser: argparse.ArgumentParser) -> str:
    formatter = argparse.HelpFormatter(parser.prog, width=100)
    formatter.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups, prefix="")
    return formatter.format_help().strip()


def _flag(action: argparse.Action) -> str:
    if not action.option_strings:
        return action.metavar or action.dest
    value = "" if action.nargs == 0 else f" {action.metavar or action.dest.upper()}"
    return ", ".join(action.option_strings) + value


def commands_markdown() -> str:
    """docs/commands.md: per command its one-line help, usage, description and arguments, from the parser."""
    from pounding.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    short = {c.dest: c.help for c in sub._choices_actions}
    parts = [INTRO]
    for name, sp in sub.choices.items():
        rows = [f"| `{_flag(a)}` | {(a.help or '').replace('%%', '%').replace('|', chr(92) + '|')} |"
                for a in sp._actions if not isinstance(a, argparse._HelpAction)]
        parts.append(f"## `pounding {name}`\n\n{short[name][0].upper()}{short[name][1:]}.\n\n```\n{_usage(sp)}\n```\n\n"
                     f"{sp.description or ''}\n\n| argument | meaning |\n|---|---|\n" + "\n".join(rows) + "\n")
    return "\n".join(parts)


def test_commands_page_is_the_command_lines_own_help():
    """docs/commands.md lists every command and option with the help text `--help` prints."""
    assert (DOCS / "commands.md").read_text() == commands_markdown(), "rewrite it: python tests/test_docs.py"


if __name__ == "__main__":
    (DOCS / "commands.md").write_text(commands_markdown())
    print(DOCS / "commands.md")
