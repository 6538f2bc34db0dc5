"""What the docs take from the sluice binary at build time, so that nothing of it is copied by hand.

- The page `case-reference` is generated from the parameter table (docs/gen_case_reference.py):
  its source file holds only the marker line below, replaced when Sphinx reads it.
- The directive `sluice-output` shows what a sluice command prints (its `--help`, `sluice cases`):

      ```{sluice-output} render --help
      ```

The binary is $SLUICE_BIN, by default build/release/sluice under the repository root. Each page
that uses it depends on the binary's file, so a rebuilt binary makes Sphinx read those pages again.
"""

from __future__ import annotations

import sys
from pathlib import Path

from docutils import nodes
from sphinx.errors import ExtensionError
from sphinx.util.docutils import SphinxDirective

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import gen_case_reference  # noqa: E402  (docs/gen_case_reference.py)

MARKER = "<!-- generated: sluice keys --json -->"


def _binary(env) -> Path:
    try:
        binary = gen_case_reference.sluice_bin()
    except gen_case_reference.GenerationError as e:
        raise ExtensionError(str(e)) from e
    env.note_dependency(str(binary))
    env.note_dependency(gen_case_reference.__file__)
    return binary


def _read_case_reference(app, docname: str, source: list[str]) -> None:
    if docname != "case-reference":
        return
    if MARKER not in source[0]:
        raise ExtensionError(f"docs/case-reference.md must hold the line {MARKER!r}, which the generated reference replaces")
    try:
        page = gen_case_reference.generate(_binary(app.env), title=False)
    except gen_case_reference.GenerationError as e:
        raise ExtensionError(str(e)) from e
    source[0] = source[0].replace(MARKER, page)


class SluiceOutput(SphinxDirective):
    """```{sluice-output} ARGS``` : a literal block with `$ sluice ARGS` and what it prints."""

    required_arguments = 1
    final_argument_whitespace = True
    has_content = False

    def run(self):
        args = self.arguments[0].split()
        try:
            text = gen_case_reference.run_sluice(args, _binary(self.env))
        except gen_case_reference.GenerationError as e:
            raise self.error(str(e))
        block = nodes.literal_block(text="$ sluice " + " ".join(args) + "\n" + text.rstrip("\n"))
        block["language"] = "text"
        return [block]


def setup(app):
    app.connect("source-read", _read_case_reference)
    app.add_directive("sluice-output", SluiceOutput)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
