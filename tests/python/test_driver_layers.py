"""No upward include in driver/ (issue 36): each room's files include only
their own room and the rooms below it, in the order of the libraries that
DEVELOPERS.md lists (each library links the ones below it). The walls room
holds two libraries: the walls (below detection) and the servo walls (over
compliance and energy)."""

import re
from pathlib import Path

DRIVER = Path(__file__).resolve().parents[2] / "driver"

#: The rooms from the bottom up.
LAYERS = ("contact", "bodies", "walls", "detection", "compliance", "energy",
          "servo_walls", "parallel", "dynamics", "io", "simulation", "apps")

INCLUDE = re.compile(r'#include [<"]([a-z_]+)/([A-Za-z_]+)\.h[>"]')


def layer(room: str, name: str) -> str:
    return "servo_walls" if room == "walls" and name.startswith(
        "servo_walls") else room


def upward_includes(driver: Path = DRIVER) -> list:
    rank = {name: k for k, name in enumerate(LAYERS)}
    bad = []
    for path in sorted(driver.rglob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        room = path.relative_to(driver).parts[0]
        mine = layer(room, path.name)
        for m in INCLUDE.finditer(path.read_text()):
            if m.group(1) not in rank:
                continue
            theirs = layer(m.group(1), m.group(2))
            if rank[theirs] > rank[mine]:
                bad.append(f"{path.relative_to(driver)} ({mine}) includes "
                           f"{m.group(1)}/{m.group(2)}.h ({theirs})")
    return bad


def test_every_driver_room_is_a_layer():
    rooms = {p.name for p in DRIVER.iterdir() if p.is_dir()}
    assert rooms <= set(LAYERS), sorted(rooms - set(LAYERS))


def test_no_upward_include_in_the_driver():
    assert upward_includes() == []


def test_an_upward_include_is_found(tmp_path):
    # The check itself: a lower room including a higher one is reported.
    (tmp_path / "bodies").mkdir()
    (tmp_path / "bodies" / "x.h").write_text(
        "#include <dynamics/moreau_jean.h>\n#include <contact/nlgs.h>\n")
    assert upward_includes(tmp_path) == [
        "bodies/x.h (bodies) includes dynamics/moreau_jean.h (dynamics)"]
