"""The ./softpack script and softpack.cli name the same commands.

The script refuses an unknown command before it installs or builds
anything, so it lists the commands it accepts; every one but its own
(build, test, fclib, env) goes to softpack.cli, whose COMMANDS maps each
to its module. A command added to one list and not the other would be
refused by the script or fail in the CLI: this test is what keeps the two
lists one. Each command is also in README's table.
"""

import re
from pathlib import Path

from softpack import cli

ROOT = Path(__file__).resolve().parents[2]
#: What the script runs itself (the build, CTest + pytest, the FCLIB
#: solver); `env` is answered before the accepted list is read
SCRIPT_OWN = {"build", "test", "fclib"}


def accepted_by_script():
    """The commands of the script's `case` pattern that accepts them."""
    text = (ROOT / "softpack").read_text()
    match = re.search(r"\n\s*(build \| run \|[^)]*)\) ;;", text)
    assert match, "the script's list of accepted commands was not found"
    return {word.strip() for word in
            match.group(1).replace("\\\n", " ").split("|")}


def test_the_script_accepts_exactly_what_it_can_dispatch():
    assert accepted_by_script() == set(cli.COMMANDS) | SCRIPT_OWN


def test_every_command_is_in_the_readme():
    readme = (ROOT / "README.md").read_text()
    missing = [c for c in sorted(accepted_by_script() | {"env"})
               if not re.search(rf"`\./softpack {re.escape(c)}[` ]", readme)]
    assert not missing
