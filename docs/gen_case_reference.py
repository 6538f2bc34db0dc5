#!/usr/bin/env python3
"""The case-file reference, generated from the program's parameter table.

Every case key is declared once, in src/sluice/case/parameter_table.cpp. `sluice keys --json` prints
them (key, type, unit, default, 3D default, allowed range or choices, description), and the template
`sluice init` writes carries each section's one-line description. This script turns both into one
Markdown page, grouped by section: [case], [domain], ..., [[water]], [[wall]], [[probe]]. Nothing in
it is written by hand, so the page cannot disagree with the program that built it.

The docs build (docs/conf.py) calls it for docs/case-reference.md; run alone, it prints the page:

    SLUICE_BIN=build/release/sluice python3 docs/gen_case_reference.py > /tmp/case-reference.md

SLUICE_BIN names the sluice binary; by default build/release/sluice under the repository root.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent

# The sections in the order of the case file. The program's own order is the order of `sluice keys`;
# this list only says which sections are repeated tables ([[water]]) and is checked against the keys.
TABLE_SECTIONS = ("case", "domain", "tank", "fluid", "physics", "damping", "release", "time", "output")
ARRAY_SECTIONS = ("water", "wall", "probe")


class GenerationError(RuntimeError):
    pass


def sluice_bin() -> Path:
    """The sluice binary: $SLUICE_BIN (relative to the working directory), else build/release/sluice
    under the repository root."""
    env = os.environ.get("SLUICE_BIN")
    path = Path(env).resolve() if env else REPO_ROOT / "build" / "release" / "sluice"
    if not path.is_file() or not os.access(path, os.X_OK):
        raise GenerationError(
            f"the sluice binary {path} is missing or not executable: build it with `make build-sluice`, "
            "or point SLUICE_BIN at one")
    return path


def run_sluice(args: list[str], binary: Path | None = None) -> str:
    """Runs `sluice ARGS` with argv[0] = "sluice" (so that usage lines read `sluice ...`), returns stdout."""
    binary = binary or sluice_bin()
    env = dict(os.environ)
    # The program restarts itself once to set OpenMP's wait policy unless it is set; set it here.
    env.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    result = subprocess.run(["sluice", *args], executable=str(binary), capture_output=True, text=True, env=env,
                            check=False)
    if result.returncode != 0:
        raise GenerationError(f"`sluice {' '.join(args)}` failed with status {result.returncode}: {result.stderr.strip()}")
    return result.stdout


def load_keys(binary: Path) -> list[dict]:
    keys = json.loads(run_sluice(["keys", "--json"], binary))
    if not isinstance(keys, list) or not keys:
        raise GenerationError("`sluice keys --json` printed no keys")
    for k in keys:
        for field in ("key", "section", "type", "description", "allowed"):
            if field not in k:
                raise GenerationError(f"`sluice keys --json`: {k.get('key', '?')} has no '{field}'")
    return keys


def section_descriptions(binary: Path) -> dict[str, str]:
    """Each section's description, from the comment above its header in the template `sluice init`
    writes (the 3D case spheric2's: it has every section, [[wall]] and [[probe]] included)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "template.toml"
        run_sluice(["init", "--from", "spheric2", str(path)], binary)
        lines = path.read_text().splitlines()
    descriptions: dict[str, str] = {}
    header = re.compile(r"^\[\[?([a-z_]+)\]\]?\s*$")
    for n, line in enumerate(lines):
        m = header.match(line)
        if not m or m.group(1) in descriptions:
            continue
        # The block of comments above the header, up to the blank line before it; its first lines
        # (before "Keys of each ...") are the section's description.
        start = n
        while start > 0 and lines[start - 1].startswith("#"):
            start -= 1
        text = []
        for comment in lines[start:n]:
            body = comment[1:].strip()
            if body.startswith("Keys of each") or comment.startswith("#  "):
                break
            text.append(body)
        descriptions[m.group(1)] = " ".join(text)
    return descriptions


def md_escape(text: str) -> str:
    """Text from the table as Markdown text: characters Markdown would take as markup are escaped."""
    return re.sub(r"([\\`*_\[\]<>|$])", r"\\\1", text)


def code(text: str) -> str:
    """Inline code that may itself hold backquotes."""
    fence = "``" if "`" in text else "`"
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def describe(description: str) -> str:
    """A description as Markdown: `name` spans stay code, the rest is escaped text."""
    parts = re.split(r"(`[^`]*`)", description)
    return "".join(p if p.startswith("`") and p.endswith("`") and len(p) > 1 else md_escape(p) for p in parts)


# Descriptions in the parameter table point to the page and section of this site that give the
# measurements behind a choice, as `docs/<page>.md, "<Section>"` (which a reader of `sluice init`'s
# template can open as it is). Each becomes a link here; a page or section that does not exist, or a
# pointer to the README (whose sections are pages of this site now), stops the build.
POINTER = re.compile(r'docs/([a-z0-9/_-]+\.md), "([^"]+)"')


def slug(title: str) -> str:
    return re.sub(r"[^a-z0-9 -]", "", title.lower()).strip().replace(" ", "-")


def link_pointers(key: str, text: str) -> str:
    if "README" in text:
        raise GenerationError(f"{key}'s description points to the README; point it to a page of docs/ instead, as "
                              'docs/<page>.md, "<Section>"')

    def link(m: re.Match) -> str:
        page, section = m.group(1), m.group(2)
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), page)
        if not os.path.exists(path):
            raise GenerationError(f"{key}'s description points to docs/{page}, which does not exist")
        titles = [line.lstrip("#").strip() for line in open(path, encoding="utf-8") if line.startswith("#")]
        if slug(section) not in [slug(t) for t in titles]:
            raise GenerationError(f'{key}\'s description points to "{section}" in docs/{page}, which has no such heading')
        return f"[{titles[0]}: {section}]({page}#{slug(section)})"

    return POINTER.sub(link, text)


def label(key: str) -> str:
    return "key-" + key.replace(".", "-")


def key_block(k: dict, array: bool) -> list[str]:
    key = k["key"]
    name = key.split(".", 1)[1]
    heading = f"`{name}`" if array else f"`{key}`"
    out = [f"({label(key)})=", f"### {heading}", ""]
    out.append(link_pointers(key, describe(k["description"])))
    out.append("")
    facts = [("type", k["type"])]
    if k.get("unit"):
        facts.append(("unit", code(k["unit"])))
    if k.get("required") or "default" not in k:
        facts.append(("default", "none: required"))
    else:
        facts.append(("default", code(k["default"])))
    if "default_3d" in k:
        facts.append(("default in 3D", code(k["default_3d"])))
    facts.append(("allowed", md_escape(k["allowed"])))
    if k.get("only_3d"):
        facts.append(("dimension", "3D cases only (an error in a 2D case)"))
    if array:
        set_key = f"{k['section']}[0].{name}"
        facts.append(("on the command line", code(f"--set {set_key}=...")))
    # A field list (MyST's fieldlist extension): one line a fact.
    for what, value in facts:
        out.append(f":{what}: {value}")
    out.append("")
    return out


def markdown(keys: list[dict], descriptions: dict[str, str], version: str, title: bool = True) -> str:
    sections: dict[str, list[dict]] = {}
    for k in keys:
        sections.setdefault(k["section"], []).append(k)
    unknown = [s for s in sections if s not in TABLE_SECTIONS + ARRAY_SECTIONS]
    if unknown:
        raise GenerationError(f"sections the generator does not know: {unknown}; add them to TABLE_SECTIONS or "
                              "ARRAY_SECTIONS in docs/gen_case_reference.py")
    out = ["# Case-file reference", ""] if title else []
    out += [
        f"Every key a case file may hold, generated from the program's parameter table by `sluice keys --json` "
        f"({md_escape(version)}); `sluice keys` prints the same in a terminal and `sluice init` writes it as "
        "comments in a case file. A key left out takes its default. Vectors have two components in a 2D case "
        "and three in a 3D case (`domain.dimension`); a default shown for 2D has a third component of 0 in 3D "
        "unless a 3D default is given. Values are TOML: numbers, `true`/`false`, strings in quotes, arrays in "
        "brackets. See [Case files](case-files.md) for how a case is written and overridden with `--set`.",
        "",
        f"{len(keys)} keys in {len(sections)} sections:",
        "",
    ]
    for s in sections:
        bracket = f"[[{s}]]" if s in ARRAY_SECTIONS else f"[{s}]"
        out.append(f"- [`{bracket}`](section-{s}): " + ", ".join(
            f"[`{k['key'].split('.', 1)[1]}`]({label(k['key'])})" for k in sections[s]))
    out.append("")
    for s, ks in sections.items():
        array = s in ARRAY_SECTIONS
        bracket = f"[[{s}]]" if array else f"[{s}]"
        out += [f"(section-{s})=", f"## `{bracket}`", ""]
        if descriptions.get(s):
            out += [describe(descriptions[s]), ""]
        if array:
            out += [f"A case may hold any number of `{bracket}` tables, numbered from 0 in file order; "
                    f"`--set '{s}[1].KEY=VALUE'` (or `{s}.1.KEY=VALUE`) changes one of them.", ""]
        for k in ks:
            out += key_block(k, array)
    return "\n".join(out).rstrip() + "\n"


def generate(binary: Path | None = None, title: bool = True) -> str:
    """The page; without its title when it goes under the title of docs/case-reference.md."""
    binary = binary or sluice_bin()
    version = run_sluice(["--version"], binary).splitlines()[0].strip()
    return markdown(load_keys(binary), section_descriptions(binary), version, title)


def main() -> int:
    try:
        page = generate()
    except GenerationError as e:
        print(f"gen_case_reference: {e}", file=sys.stderr)
        return 1
    if len(sys.argv) > 1:
        Path(sys.argv[1]).write_text(page)
    else:
        sys.stdout.write(page)
    return 0


if __name__ == "__main__":
    sys.exit(main())
