"""``linkstress import SKETCH --scene`` on linkages the tests draw assembled with ezdxf: six-bars of
random lengths, a crank pin in a slotted lever (with a collar block or without), a ram on a ground
that is not drawn, a lift cylinder, and drawings that are not one-DOF (refused, naming).

Every drawing is made here from joint positions, so the truth is known: each link a plate around
its pins (the convex hull of its pins grown by half its width) with a round pin hole and a POINT at
each, a block a rectangle with its one pin. The positions the written scene gives away from the
drawn input are checked against step-by-step circle and line intersections computed here, never
the engine's, each intersection taken nearest the last one along 1 deg steps (the assembly drawn,
followed).
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from shapely.geometry import MultiPoint

from linkstress.cli import main
from linkstress.importers import read_sketch
from linkstress.importers.pins import shared_joints
from linkstress.importers.slides import find_slides
from linkstress.kinematics.motion import angle_motion, stroke_motion
from linkstress.kinematics.solve import solve_machine
from linkstress.scene.reader import load_scene

WIDTH = 0.04
"""Plate width [m]."""
HOLE = 0.012
"""Pin hole diameter [m]."""


def e(deg: float) -> np.ndarray:
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


def rotate(v: np.ndarray, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def meet(p: np.ndarray, r: float, q: np.ndarray, s: float, near: np.ndarray) -> np.ndarray | None:
    """The intersection of the circles (p, r) and (q, s) nearest ``near``, or None when they miss."""
    d = q - p
    length = math.hypot(*d)
    along = (r * r - s * s + length * length) / (2 * length)
    h2 = r * r - along * along
    if h2 < 0:
        return None
    base = p + along * d / length
    n = np.array([-d[1], d[0]]) / length * math.sqrt(h2)
    return min((base + n, base - n), key=lambda x: math.hypot(*(x - near)))


def stepped(drawn: float, targets, pose):
    """``pose(value, last)`` at each of ``targets``, stepping 1 deg from the ``drawn`` input so that
    every intersection is the one nearest the last: {target: points or None where it misses}."""
    out = {}
    for target in targets:
        last = pose(drawn, None)
        steps = max(1, math.ceil(abs(target - drawn)))
        for value in np.linspace(drawn, target, steps + 1)[1:]:
            last = pose(value, last) if last is not None else None
        out[target] = last
    return out


class Drawing:
    """A DXF in metres: links on their own layers as plates with pin holes and POINTs."""

    def __init__(self) -> None:
        self.doc = ezdxf.new("R2013", units=6)
        self.msp = self.doc.modelspace()

    def _layer(self, layer: str) -> dict:
        if layer not in self.doc.layers:
            self.doc.layers.add(layer)
        return {"layer": layer}

    def plate(self, layer: str, pins, in_material: int = 0, width: float = WIDTH) -> None:
        """A plate ``width`` wide around ``pins`` with a POINT at each and a hole at each but the last
        ``in_material`` (a joint in the material: a point on a line, a foot)."""
        attrs = self._layer(layer)
        shape = MultiPoint([tuple(p) for p in pins]).convex_hull.buffer(width / 2, quad_segs=16)
        self.msp.add_lwpolyline(list(shape.exterior.coords)[:-1], close=True, dxfattribs=attrs)
        for k, p in enumerate(pins):
            if k < len(pins) - in_material:
                self.msp.add_circle(tuple(p), HOLE / 2, dxfattribs=attrs)
            self.msp.add_point(tuple(p), dxfattribs=attrs)

    def block(self, layer: str, pin, direction, length: float, width: float, behind: float = 0.0) -> None:
        """A rectangle ``length`` along ``direction`` and ``width`` across about its one ``pin``, its
        centre ``behind`` [m] back from the pin along ``direction``."""
        attrs = self._layer(layer)
        u = np.asarray(direction, float) / math.hypot(*direction)
        n = np.array([-u[1], u[0]])
        c = np.asarray(pin, float) - behind * u
        corners = [c - u * length / 2 - n * width / 2, c + u * length / 2 - n * width / 2,
                   c + u * length / 2 + n * width / 2, c - u * length / 2 + n * width / 2]
        self.msp.add_lwpolyline([tuple(p) for p in corners], close=True, dxfattribs=attrs)
        self.msp.add_circle(tuple(pin), HOLE / 2, dxfattribs=attrs)
        self.msp.add_point(tuple(pin), dxfattribs=attrs)

    def slot(self, layer: str, start, end, width: float) -> None:
        """A slot (a stadium-shaped hole) from ``start`` to ``end``."""
        shape = MultiPoint([tuple(start), tuple(end)]).convex_hull.buffer(width / 2, quad_segs=16)
        self.msp.add_lwpolyline(list(shape.exterior.coords)[:-1], close=True, dxfattribs=self._layer(layer))

    def save(self, path: Path) -> Path:
        self.doc.saveas(path)
        return path


def import_scene(sketch: Path, capsys) -> tuple[Path, dict, str]:
    out = sketch.with_suffix(".toml")
    assert main(["import", str(sketch), "--scene", str(out)]) == 0
    return out, tomllib.loads(out.read_text()), capsys.readouterr().out


def solved_as(printed: str) -> list[tuple[str, frozenset[str]]]:
    """The groups the import printed the linkage is solved in: (kind, its links) in solving order."""
    line = next(line for line in printed.splitlines() if line.startswith("  solved as: "))
    return [(kind, frozenset(links.split(", "))) for kind, links in re.findall(r"([A-Za-z ]+) \(([^)]*)\)(?:, )?", line[13:])]


def groups(*spec: tuple[str, str]) -> list[tuple[str, frozenset[str]]]:
    return [(kind, frozenset(links.split(", "))) for kind, links in spec]


def joints_at(scene_path: Path, values, named: dict[str, tuple[str, np.ndarray]], stroke: bool = False):
    """Where the written scene puts each ``named`` point (its link and where it is drawn) at the inputs
    ``values``: {name: (P, 2)} [m], with the feasibility of each position."""
    scene = load_scene(scene_path)
    motion = stroke_motion(values) if stroke else angle_motion(values)
    solved = solve_machine(scene.machine, motion)
    out = {}
    for name, (link, drawn) in named.items():
        joints = scene.links[link].joints
        k = int(np.argmin(np.hypot(*(joints - drawn).T)))
        assert math.hypot(*(joints[k] - drawn)) < 1e-9
        out[name] = solved.links[link].point(scene.links[link].to_member(joints[k]))[0]
    return out, solved.feasible


def agree(scene_path: Path, drawn_input: float, targets, pose, named, stroke: bool = False) -> int:
    """The written scene puts every named point where ``pose`` does, within 1e-9 m, at every target
    where the truth assembles (and the scene must assemble there too); how many targets did."""
    truth = stepped(drawn_input, targets, pose)
    got, feasible = joints_at(scene_path, np.array(targets, float), named, stroke)
    checked = 0
    for k, target in enumerate(targets):
        if truth[target] is None:
            continue
        assert feasible[k], target
        for name in named:
            assert math.hypot(*(got[name][k] - truth[target][name])) < 1e-9, (target, name)
        checked += 1
    return checked


# -- six-bars of random lengths ----------------------------------------------------------------


def four_bar(rng) -> dict[str, np.ndarray]:
    """O2 (0, 0), O4 on +x, a crank-rocker drawn at a random crank angle, B left of A -> O4."""
    o2, o4 = np.zeros(2), np.array([rng.uniform(0.8, 1.1), 0.0])
    theta = rng.uniform(0.0, 360.0)
    a = o2 + rng.uniform(0.15, 0.22) * e(theta)
    b = meet(a, rng.uniform(0.85, 1.05), o4, rng.uniform(0.7, 0.9), a + rotate(o4 - a, 90.0))
    return {"O2": o2, "O4": o4, "A": a, "B": b, "theta": theta}


def fourbar_pose(at: dict[str, np.ndarray]):
    """The crank angle -> A, B pose of ``at``'s four-bar, B nearest its last place."""
    r2, l3, l4 = (math.hypot(*(at[q] - at[p])) for p, q in (("O2", "A"), ("A", "B"), ("O4", "B")))

    def pose(theta: float, last):
        a = at["O2"] + r2 * e(theta)
        b = meet(a, l3, at["O4"], l4, at["B"] if last is None else last["B"])
        return None if b is None else {"A": a, "B": b}

    return pose


def rigid(p: np.ndarray, q: np.ndarray, x: np.ndarray):
    """A function placing the point ``x``, rigid with the segment p -> q as drawn, on a moved p -> q."""
    d = q - p
    ang = math.atan2(d[1], d[0])
    local = rotate(x - p, -math.degrees(ang))

    def place(p2: np.ndarray, q2: np.ndarray) -> np.ndarray:
        d2 = q2 - p2
        return p2 + rotate(local, math.degrees(math.atan2(d2[1], d2[0])))

    return place


def stephenson3(rng) -> dict[str, np.ndarray]:
    """A Stephenson III six-bar: the four-bar's ternary coupler A, B, P; a dyad P -> Q -> O6."""
    at = four_bar(rng)
    a, b = at["A"], at["B"]
    at["P"] = a + rotate((b - a) / math.hypot(*(b - a)), rng.uniform(30.0, 60.0)) * rng.uniform(0.35, 0.6)
    gamma = rng.uniform(0.0, 360.0)
    at["Q"] = at["P"] + rng.uniform(0.5, 0.8) * e(gamma)
    at["O6"] = at["Q"] + rng.uniform(0.5, 0.8) * e(gamma + rng.uniform(60.0, 120.0))
    return at


def watt1(rng) -> dict[str, np.ndarray]:
    """A Watt I six-bar: the four-bar's coupler A, B, C and rocker O4, B, D both ternary, joined at B;
    a dyad C -> E -> D between them."""
    at = four_bar(rng)
    a, b, o4 = at["A"], at["B"], at["O4"]
    at["C"] = a + rotate((b - a) / math.hypot(*(b - a)), rng.uniform(-60.0, -30.0)) * rng.uniform(0.4, 0.6)
    at["D"] = o4 + rotate((b - o4) / math.hypot(*(b - o4)), rng.uniform(-60.0, -30.0)) * rng.uniform(0.4, 0.6)
    c, d = at["C"], at["D"]
    mid, n = (c + d) / 2, rotate((d - c) / math.hypot(*(d - c)), -90.0)
    at["E"] = mid + n * rng.uniform(0.3, 0.5) * math.hypot(*(d - c))
    return at


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("ground", ["frame", None], ids=["ground drawn", "ground not drawn"])
def test_a_stephenson_six_bar_of_random_lengths_imports_as_a_linkage_that_moves_as_its_dyads_do(tmp_path, capsys,
                                                                                              seed, ground):
    at = stephenson3(np.random.default_rng(seed))
    drawing = Drawing()
    drawing.plate("crank", [at["O2"], at["A"]])
    drawing.plate("coupler", [at["A"], at["B"], at["P"]])
    drawing.plate("rocker", [at["O4"], at["B"]])
    drawing.plate("link", [at["P"], at["Q"]])
    # The lever's tool end T, a POINT in its material: no pin, and no fixed pivot of a ground not drawn.
    tool = at["O6"] + 1.4 * (at["Q"] - at["O6"])
    drawing.plate("lever", [at["O6"], at["Q"], tool], in_material=1)
    if ground:
        drawing.plate(ground, [at["O2"], at["O4"], at["O6"]])
    out, written, printed = import_scene(drawing.save(tmp_path / "stephenson.dxf"), capsys)
    mechanism = written["mechanisms"]["main"]
    assert mechanism["type"] == "linkage" and mechanism["input"]["link"] == "crank"
    assert solved_as(printed) == groups(("input", "crank"), ("RRR dyad", "coupler, rocker"), ("RRR dyad", "link, lever"))
    assert len(mechanism["pins"]) == 7
    if ground is None:
        # The fixed pivots, the pin holes one link alone has, by x then y.
        pivots = sorted((tuple(at[k]) for k in ("O2", "O4", "O6")))
        assert np.allclose(written["links"]["ground"]["joints"], pivots, atol=1e-12)
    four = fourbar_pose(at)
    p_on = rigid(at["A"], at["B"], at["P"])
    l5, l6 = math.hypot(*(at["Q"] - at["P"])), math.hypot(*(at["Q"] - at["O6"]))

    def pose(theta, last):
        moved = four(theta, last)
        if moved is None:
            return None
        p = p_on(moved["A"], moved["B"])
        q = meet(p, l5, at["O6"], l6, at["Q"] if last is None else last["Q"])
        return None if q is None else {**moved, "P": p, "Q": q, "T": at["O6"] + 1.4 * (q - at["O6"])}

    named = {"A": ("crank", at["A"]), "B": ("rocker", at["B"]), "P": ("link", at["P"]), "Q": ("lever", at["Q"]),
             "T": ("lever", tool)}
    targets = [at["theta"] + d for d in (-40.0, -15.0, 10.0, 35.0)]
    assert agree(out, at["theta"], targets, pose, named) == 4


def test_a_six_bar_drawn_with_its_dyad_in_line_is_refused_at_its_toggle(tmp_path, capsys):
    at = stephenson3(np.random.default_rng(1))
    # O6 on the line P -> Q, 0.7 m beyond Q: the link and the lever drawn in line, neither assembly drawn.
    at["O6"] = at["Q"] + 0.7 * (at["Q"] - at["P"]) / math.hypot(*(at["Q"] - at["P"]))
    drawing = Drawing()
    for layer, pins in {"crank": ["O2", "A"], "coupler": ["A", "B", "P"], "rocker": ["O4", "B"], "link": ["P", "Q"],
                        "lever": ["O6", "Q"], "frame": ["O2", "O4", "O6"]}.items():
        drawing.plate(layer, [at[k] for k in pins])
    out = tmp_path / "toggle.toml"
    assert main(["import", str(drawing.save(tmp_path / "toggle.dxf")), "--scene", str(out)]) == 2
    err = capsys.readouterr().err
    assert "the mechanism as drawn does not assemble at the drawn input: toggle of the RRR dyad" in err
    assert "lever" in err and "link" in err and not out.exists()


@pytest.mark.parametrize("seed", [4, 5, 6])
def test_a_watt_i_six_bar_of_random_lengths_imports_as_a_linkage_that_moves_as_its_dyads_do(tmp_path, capsys, seed):
    at = watt1(np.random.default_rng(seed))
    drawing = Drawing()
    # No layer named crank: the input is the shortest link pinned to the ground.
    drawing.plate("arm", [at["O2"], at["A"]])
    drawing.plate("coupler", [at["A"], at["B"], at["C"]])
    drawing.plate("rocker", [at["O4"], at["B"], at["D"]])
    drawing.plate("link_ce", [at["C"], at["E"]])
    drawing.plate("link_de", [at["D"], at["E"]])
    drawing.plate("base", [at["O2"], at["O4"]])
    out, written, printed = import_scene(drawing.save(tmp_path / "watt.dxf"), capsys)
    mechanism = written["mechanisms"]["main"]
    assert (mechanism["type"], mechanism["ground"], mechanism["input"]["link"]) == ("linkage", "base", "arm")
    assert solved_as(printed) == groups(("input", "arm"), ("RRR dyad", "coupler, rocker"), ("RRR dyad", "link_ce, link_de"))
    four = fourbar_pose(at)
    c_on, d_on = rigid(at["A"], at["B"], at["C"]), rigid(at["O4"], at["B"], at["D"])
    l_ce, l_de = math.hypot(*(at["E"] - at["C"])), math.hypot(*(at["E"] - at["D"]))

    def pose(theta, last):
        moved = four(theta, last)
        if moved is None:
            return None
        c, d = c_on(moved["A"], moved["B"]), d_on(at["O4"], moved["B"])
        x = meet(c, l_ce, d, l_de, at["E"] if last is None else last["E"])
        return None if x is None else {**moved, "C": c, "D": d, "E": x}

    named = {"B": ("coupler", at["B"]), "C": ("link_ce", at["C"]), "D": ("link_de", at["D"]), "E": ("link_ce", at["E"])}
    targets = [at["theta"] + d for d in (-30.0, -10.0, 20.0, 45.0)]
    assert agree(out, at["theta"], targets, pose, named) == 4


def test_an_eight_bar_with_a_quaternary_coupler_imports_with_its_four_pins_on_one_link(tmp_path, capsys):
    # A four-bar whose coupler carries two more pins, C and D, each driving a dyad to the ground:
    # n = 8, j1 = 10, F = 3 (8 - 1) - 2 x 10 = 1.
    rng = np.random.default_rng(8)
    at = four_bar(rng)
    a, b = at["A"], at["B"]
    along = (b - a) / math.hypot(*(b - a))
    at["C"], at["D"] = a + rotate(along, 50.0) * 0.4, a + rotate(along, -40.0) * 0.5
    for point, (pin, pivot) in {"C": ("E", "O6"), "D": ("F", "O8")}.items():
        gamma = rng.uniform(0.0, 360.0)
        at[pin] = at[point] + 0.6 * e(gamma)
        at[pivot] = at[pin] + 0.6 * e(gamma + 90.0)
    drawing = Drawing()
    for layer, pins in {"crank": ["O2", "A"], "coupler": ["A", "B", "C", "D"], "rocker": ["O4", "B"], "ce": ["C", "E"],
                        "e6": ["O6", "E"], "df": ["D", "F"], "f8": ["O8", "F"], "frame": ["O2", "O4", "O6", "O8"]}.items():
        drawing.plate(layer, [at[k] for k in pins])
    out, written, printed = import_scene(drawing.save(tmp_path / "eight.dxf"), capsys)
    pins = written["mechanisms"]["main"]["pins"]
    assert len(pins) == 10 and sorted(j for pin in pins for j in pin if j.startswith("coupler:")) == [
        "coupler:0", "coupler:1", "coupler:2", "coupler:3"]
    assert solved_as(printed) == groups(("input", "crank"), ("RRR dyad", "coupler, rocker"), ("RRR dyad", "ce, e6"),
                                        ("RRR dyad", "df, f8"))
    four = fourbar_pose(at)
    c_on, d_on = rigid(a, b, at["C"]), rigid(a, b, at["D"])
    arms = {k: (math.hypot(*(at[p] - at[q])), math.hypot(*(at[p] - at[o]))) for k, p, q, o in
            (("E", "E", "C", "O6"), ("F", "F", "D", "O8"))}

    def pose(theta, last):
        moved = four(theta, last)
        if moved is None:
            return None
        moved |= {"C": c_on(moved["A"], moved["B"]), "D": d_on(moved["A"], moved["B"])}
        for pin, point, pivot in (("E", "C", "O6"), ("F", "D", "O8")):
            moved[pin] = meet(moved[point], arms[pin][0], at[pivot], arms[pin][1], at[pin] if last is None else last[pin])
            if moved[pin] is None:
                return None
        return moved

    named = {"C": ("coupler", at["C"]), "D": ("coupler", at["D"]), "E": ("ce", at["E"]), "F": ("df", at["F"])}
    targets = [at["theta"] + d for d in (-30.0, -10.0, 15.0, 40.0)]
    assert agree(out, at["theta"], targets, pose, named) == 4


# -- sliders -------------------------------------------------------------------------------------

O2, O4 = np.array([0.0, 0.3]), np.array([0.0, 0.0])
CRANK, LEVER = 0.1, 0.55
"""A quick-return: the crank O2 -> A (0.1 m) turns about O2, 0.3 m above the lever's pivot O4; the
crank pin A runs in the slot of the lever O4 -> T (0.55 m)."""


def quick_return(theta: float) -> dict[str, np.ndarray]:
    a = O2 + CRANK * e(theta)
    u = (a - O4) / math.hypot(*(a - O4))
    return {"A": a, "T": O4 + LEVER * u, "u": u}


def slotted_lever(drawing: Drawing, theta: float, collar: bool, offset: float = 0.0) -> None:
    """The crank, the slotted lever (its slot from 0.15 to 0.45 m along it, 30 mm wide, ``offset`` to its
    left) and, with ``collar``, a 50 x 30 mm collar on the crank pin in the slot."""
    at = quick_return(theta)
    u = at["u"]
    n = np.array([-u[1], u[0]])
    drawing.plate("crank", [O2, at["A"]])
    drawing.plate("lever", [O4, at["T"]])
    drawing.slot("lever", O4 + 0.15 * u + offset * n, O4 + 0.45 * u + offset * n, 0.03)
    if collar:
        drawing.block("collar", at["A"], u, 0.05, 0.03)


def lever_pose(theta: float, last) -> dict[str, np.ndarray]:
    at = quick_return(theta)
    return {"A": at["A"], "T": at["T"]}


@pytest.mark.parametrize("collar", [True, False], ids=["a collar block in the slot", "the pin alone in the slot"])
def test_a_crank_pin_in_a_slot_of_a_moving_lever_slides_on_the_slots_axis(tmp_path, capsys, collar):
    theta = 35.0
    drawing = Drawing()
    slotted_lever(drawing, theta, collar)
    drawing.plate("frame", [O2, O4])
    out, written, printed = import_scene(drawing.save(tmp_path / "slotted.dxf"), capsys)
    mechanism = written["mechanisms"]["main"]
    # The lever's joints by x then y: O4 (0, 0), then T; the line runs from its pivot O4 toward T.
    slider = {"point": "crank:1", "on": "lever", "line": [0, 1]} | ({"block": "collar"} if collar else {})
    assert mechanism["sliders"] == [slider]
    assert mechanism["pins"] == [["frame:0", "lever:0"], ["frame:1", "crank:0"]]
    assert solved_as(printed) == groups(("input", "crank"), ("RPR dyad", "lever"))
    # The slot's axis through O4: the lever points at the crank pin, T = O4 + 0.55 m toward A.
    named = {"A": ("crank", quick_return(theta)["A"]), "T": ("lever", quick_return(theta)["T"])}
    targets = [theta + d for d in (-150.0, -60.0, 90.0, 200.0)]
    assert agree(out, theta, targets, lever_pose, named) == 4


@pytest.mark.parametrize("collar", [True, False], ids=["a collar block in the slot", "the pin alone in the slot"])
def test_a_pin_in_a_slot_travels_until_it_or_its_collar_meets_the_slots_end(tmp_path, collar):
    # The slot runs 0.15 to 0.45 m along the lever, 30 mm wide: its round ends reach 0.135 and
    # 0.465 m. The crank pin at 35 deg is |A - O4| along; a pin alone stops where its centre meets an
    # end circle's (0.15, 0.45 m), a 50 mm collar where its end meets the slot's (0.025 m short of it).
    theta = 35.0
    drawing = Drawing()
    slotted_lever(drawing, theta, collar)
    drawing.plate("frame", [O2, O4])
    sketch = read_sketch(drawing.save(tmp_path / "slotted.dxf"))
    links = {link.name: link for link in sketch.links}
    (slide,) = find_slides(links, shared_joints(sketch.links, sketch.gap_tolerance_m), "frame", sketch.gap_tolerance_m)
    along = math.hypot(*quick_return(theta)["A"])
    room = (0.135 + 0.025, 0.465 - 0.025) if collar else (0.15, 0.45)
    assert (slide.on, slide.block, slide.point) == ("lever", "collar" if collar else None, ("crank", 1))
    assert slide.direction @ quick_return(theta)["u"] == pytest.approx(1.0, abs=1e-12)
    assert slide.travel == pytest.approx((room[0] - along, room[1] - along), abs=1e-9)


def test_a_slot_whose_axis_misses_the_levers_joints_is_refused_naming_the_lever(tmp_path, capsys):
    theta = 35.0
    drawing = Drawing()
    # The slot 10 mm to the left of O4 -> T, the crank pin on its axis: the lever turns the crank pin's line off O4.
    at = quick_return(theta)
    u = at["u"]
    n = np.array([-u[1], u[0]])
    a = O4 + 0.3 * u + 0.01 * n
    drawing.plate("crank", [O2, a])
    drawing.plate("lever", [O4, at["T"]], width=0.1)
    drawing.slot("lever", O4 + 0.15 * u + 0.01 * n, O4 + 0.45 * u + 0.01 * n, 0.03)
    drawing.plate("frame", [O2, O4])
    sketch = drawing.save(tmp_path / "offset.dxf")
    assert main(["import", str(sketch), "--scene", str(tmp_path / "offset.toml")]) == 2
    err = capsys.readouterr().err
    assert "the pin of 'crank' in the slot of 'lever' slides along the line through" in err
    assert "no two joints of 'lever' lie on that line" in err and err.count("\n") == 1
    assert not (tmp_path / "offset.toml").exists()


RAM_Y = 0.6
"""The ram's guide line: y = 0.6 m, horizontal."""
ROD = 0.25


def shaper_pose(theta: float, last) -> dict[str, np.ndarray]:
    """The quick-return's lever end T drives the rod T -> R (0.25 m) to the ram R on y = 0.6 m, R ahead
    of T along +x (the drawn assembly)."""
    at = quick_return(theta)
    t = at["T"]
    dx = math.sqrt(ROD**2 - (RAM_Y - t[1]) ** 2)
    return {"A": at["A"], "T": t, "R": np.array([t[0] + dx, RAM_Y])}


def test_a_ram_on_a_ground_not_drawn_slides_along_its_longer_side_through_its_pin(tmp_path, capsys):
    theta = 60.0
    drawn = shaper_pose(theta, None)
    drawing = Drawing()
    slotted_lever(drawing, theta, collar=True)
    drawing.plate("rod", [drawn["T"], drawn["R"]])
    drawing.block("ram", drawn["R"], (1.0, 0.0), 0.3, 0.08)
    out, written, printed = import_scene(drawing.save(tmp_path / "shaper.dxf"), capsys)
    mechanism = written["mechanisms"]["main"]
    # The ground not drawn: the pivots O4 (0, 0) and O2 (0, 0.3) by x then y, then the ram's line,
    # through its pin R and the ram's 0.3 m length along its longer side.
    r = drawn["R"]
    assert np.allclose(written["links"]["ground"]["joints"], [O4, O2, r, r + [0.3, 0.0]], atol=1e-12)
    assert mechanism["sliders"][1] == {"point": "rod:1", "on": "ground", "line": [2, 3], "block": "ram"}
    assert solved_as(printed) == groups(("input", "crank"), ("RPR dyad", "lever"), ("RRP dyad", "rod"))
    named = {"T": ("lever", drawn["T"]), "R": ("ram", drawn["R"])}
    targets = [theta + d for d in (-120.0, -45.0, 45.0, 120.0, 240.0)]
    assert agree(out, theta, targets, shaper_pose, named) == 5


# -- a lift cylinder ---------------------------------------------------------------------------

P0, Q0 = np.array([0.0, 0.0]), np.array([0.3, -0.6])
"""The boom's pivot and the cylinder's base pin on the frame [m]."""
BOOM = 0.8
"""The cylinder's rod eye K on the boom, 0.8 m from its pivot."""


def lift(stroke: float, last) -> dict[str, np.ndarray] | None:
    """K on the circle about P0 (0.8 m) at ``stroke`` from Q0 (the cylinder's pin-to-pin length)."""
    k = meet(P0, BOOM, Q0, stroke, np.array([0.7, 0.4]) if last is None else last["K"])
    return None if k is None else {"K": k}


def lift_drawing(path: Path, barrel: str, rod: str, stroke: float) -> Path:
    """The boom (pivot P0, rod eye K, a bucket pin beyond), the frame (P0, Q0), the barrel on layer
    ``barrel`` (its base pin Q0 and a POINT on its axis at the head, 0.6 m along) and the rod on layer
    ``rod`` (a 0.5 m block ending at its eye K, lying in the barrel), drawn at ``stroke`` [m]."""
    k = lift(stroke, None)["K"]
    axis = (k - Q0) / math.hypot(*(k - Q0))
    drawing = Drawing()
    drawing.plate("frame", [P0, Q0])
    drawing.plate("boom", [P0, k, P0 + 1.2 * (k - P0) / BOOM])
    drawing.plate(barrel, [Q0, Q0 + 0.6 * axis], in_material=1)
    drawing.block(rod, k, axis, 0.5, 0.02, behind=0.22)
    return drawing.save(path)


def test_a_cylinder_named_on_its_layers_is_the_input_its_stroke_as_drawn(tmp_path, capsys):
    stroke = 0.9
    out, written, printed = import_scene(lift_drawing(tmp_path / "lift.dxf", "lift_cylinder", "piston_rod", stroke), capsys)
    mechanism = written["mechanisms"]["main"]
    # The rod's eye K is the boom's joint 1 (P0 (0, 0), then K, then the bucket pin, by x); the line
    # runs from the barrel's base pin (its joint 0) toward the POINT at its head.
    assert mechanism["sliders"] == [{"point": "boom:1", "on": "lift_cylinder", "line": [0, 1], "block": "piston_rod"}]
    assert mechanism["input"] == {"slider": 0}
    assert written["motion"]["input_stroke_m"] == pytest.approx(stroke, abs=1e-12)
    assert "block 'piston_rod' in the outline of 'lift_cylinder'" in printed
    k = lift(stroke, None)["K"]
    assert agree(out, stroke, [0.6, 0.75, 1.0, 1.2], lift, {"K": ("boom", k)}, stroke=True) == 4


def test_a_cylinder_not_named_leaves_the_input_to_the_shortest_link_pinned_to_the_ground(tmp_path, capsys):
    out, written, printed = import_scene(lift_drawing(tmp_path / "lift.dxf", "tube", "plunger", 0.9), capsys)
    mechanism = written["mechanisms"]["main"]
    # The barrel's base to its head (0.6 m) is shorter than the boom's pivot to K (0.8 m).
    assert mechanism["input"] == {"link": "tube", "pivot": 0, "to": 1}
    assert mechanism["sliders"] == [{"point": "boom:1", "on": "tube", "line": [0, 1], "block": "plunger"}]


# -- not one degree of freedom -----------------------------------------------------------------


def test_a_five_bar_has_two_degrees_of_freedom_and_is_refused_naming_the_count_and_the_links_that_float(
        tmp_path, capsys):
    o2, o5 = np.zeros(2), np.array([0.6, 0.0])
    a, b = o2 + 0.2 * e(70.0), o5 + 0.25 * e(110.0)
    c = np.array([0.3, 0.5])
    drawing = Drawing()
    for layer, pins in {"crank": [o2, a], "left": [a, c], "right": [c, b], "crank2": [o5, b], "frame": [o2, o5]}.items():
        drawing.plate(layer, pins)
    out = tmp_path / "five.toml"
    assert main(["import", str(drawing.save(tmp_path / "five.dxf")), "--scene", str(out)]) == 2
    err = capsys.readouterr().err
    # n = 5 links, j1 = 5 pins: F = 3 (5 - 1) - 2 x 5 = 2.
    assert "Gruebler: F = 3 (n - 1) - 2 j1 - j2 = 3 (5 - 1) - 2 x 5 - 0 = 2 degrees of freedom" in err
    assert "links left, right, crank2 float" in err and err.count("\n") == 1
    assert not out.exists()


def test_a_four_bar_braced_to_the_ground_locks_and_is_refused_naming_the_links(tmp_path, capsys):
    at = four_bar(np.random.default_rng(7))
    brace_end = at["A"] + 0.4 * (at["B"] - at["A"])
    drawing = Drawing()
    drawing.plate("crank", [at["O2"], at["A"]])
    drawing.plate("coupler", [at["A"], brace_end, at["B"]])
    drawing.plate("rocker", [at["O4"], at["B"]])
    drawing.plate("brace", [brace_end, np.array([0.4, -0.5])])
    drawing.plate("frame", [at["O2"], at["O4"], np.array([0.4, -0.5])])
    out = tmp_path / "braced.toml"
    assert main(["import", str(drawing.save(tmp_path / "braced.dxf")), "--scene", str(out)]) == 2
    err = capsys.readouterr().err
    # n = 5, j1 = 6: F = 3 (5 - 1) - 2 x 6 = 0.
    assert "= 3 (5 - 1) - 2 x 6 - 0 = 0 degrees of freedom" in err
    assert "lock" in err and "brace" in err
    assert not out.exists()


def test_a_drawing_with_a_problem_is_not_read_as_a_linkage_without_the_part_left_out(tmp_path, capsys):
    theta = 35.0
    at = quick_return(theta)
    u = at["u"]
    n = np.array([-u[1], u[0]])
    drawing = Drawing()
    # The slot, 30 mm wide and 10 mm off the 40 mm lever's axis, cuts its edge: the lever is left out,
    # and the crank on the frame alone would be a linkage of one degree of freedom.
    drawing.plate("crank", [O2, O4 + 0.3 * u + 0.01 * n])
    drawing.plate("lever", [O4, at["T"]])
    drawing.slot("lever", O4 + 0.15 * u + 0.01 * n, O4 + 0.45 * u + 0.01 * n, 0.03)
    drawing.plate("frame", [O2, O4])
    out = tmp_path / "cut.toml"
    assert main(["import", str(drawing.save(tmp_path / "cut.dxf")), "--scene", str(out)]) == 2
    err = capsys.readouterr().err
    assert "nor is it read as a linkage of pins and sliders while the drawing has problems" in err
    assert "layer 'lever'" in err and err.count("\n") == 1
    assert not out.exists()


def test_an_input_that_rocks_gets_a_commented_sweep_between_the_samples_next_to_its_toggles(tmp_path, capsys):
    # The double rocker of test_import_assembly (crank 0.8 m at 45 deg from O2 (0, 0), coupler 0.4,
    # output 0.7, O4 (1, 0)), its coupler's midpoint P carrying a dyad P -> Q -> O6 that closes over
    # its whole range. |A O4|^2 = 0.64 + 1 - 1.6 cos(phi) reaches b + c = 1.1 and |b - c| = 0.3 m at
    # phi = acos(1.55 / 1.6) = 14.3615 deg and acos(0.43 / 1.6) = 74.4101 deg: the samples 0.5 deg
    # apart from the drawn 45 deg that assemble run from 14.5 to 74.0 deg.
    o2, o4 = np.zeros(2), np.array([1.0, 0.0])
    a = 0.8 * e(45.0)
    b = meet(a, 0.4, o4, 0.7, a + rotate(o4 - a, 90.0))
    p = (a + b) / 2
    q = p + np.array([0.0, 0.9])
    o6 = q + np.array([0.9, 0.0])
    drawing = Drawing()
    for layer, pins in {"crank": [o2, a], "coupler": [a, p, b], "rocker": [o4, b], "link": [p, q],
                        "lever": [o6, q], "frame": [o2, o4, o6]}.items():
        drawing.plate(layer, pins)
    out, written, _ = import_scene(drawing.save(tmp_path / "rocks.dxf"), capsys)
    low, high = math.degrees(math.acos(1.55 / 1.6)), math.degrees(math.acos(0.43 / 1.6))
    assert (math.ceil(2 * low) / 2, math.floor(2 * high) / 2) == (14.5, 74.0)
    assert "# input_angle_deg = {start = 14.5, stop = 74.0, num = 201}  # a sweep: the input rocks" in out.read_text()
    assert written["motion"]["input_angle_deg"] == 45.0


def test_a_cylinders_commented_sweep_is_the_strokes_that_keep_the_rods_end_in_its_barrel(tmp_path, capsys):
    # Drawn at 0.9 m: the barrel reaches from 0.02 m behind its base pin Q0 (its round end) to 0.62 m
    # along its axis, the rod's back end lies 0.47 m behind K, 0.43 m along from Q0. That end stays in
    # the barrel from 0.45 m less to 0.19 m more stroke: 0.45 to 1.09 m, where the boom reaches
    # (|0.8 - |P0 Q0|| = 0.129 m to 0.8 + |P0 Q0| = 1.471 m, |P0 Q0| = sqrt(0.3^2 + 0.6^2) m).
    out, _, _ = import_scene(lift_drawing(tmp_path / "lift.dxf", "cylinder", "rod", 0.9), capsys)
    reach = math.hypot(*(Q0 - P0))
    assert BOOM - reach < 0.45 and 1.09 < BOOM + reach
    sweep = re.search(r"# input_stroke_m = \{start = (\S+), stop = (\S+), num = 101\}  # a sweep: where the block "
                      r"stays in its guide", out.read_text())
    assert (float(sweep[1]), float(sweep[2])) == pytest.approx((0.45, 1.09), abs=1e-12)
