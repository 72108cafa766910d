"""Every wrong key in a scene is reported with the file, its dotted path and what to do."""

from __future__ import annotations

import textwrap

import ezdxf
import pytest

from linkstress.cli import main
from linkstress.errors import SceneError
from linkstress.geometry.members import link_members
from linkstress.scene import load_scene

BASE = """
[materials.steel]
density = 7850.0

[links.crank]
joints = [[0.0, 0.0], [0.02, 0.0]]
thickness = 0.01
material = "steel"

[links.coupler]
joints = [[0.0, 0.0], [0.07, 0.0]]

[links.output]
joints = [[0.0, 0.0], [0.05, 0.0]]

[links.ground]
joints = [[0.0, 0.0], [0.06, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = {start = 0.0, stop = 350.0, num = 36}
input_speed_rad_s = 10.0
"""


def load(tmp_path, text: str):
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    return load_scene(path)


def test_the_base_scene_is_valid(tmp_path):
    scene = load(tmp_path, BASE)
    assert scene.motion.n_positions == 36


CASES = [
    # (old text, new text, expected message)
    ("thickness = 0.01", "thicknes = 0.01",
     "scene.toml: links.crank.thicknes: unknown key; allowed keys are: sketch, layer, units, joints, thickness,"),
    ("thickness = 0.01", "thickness = -0.01", "scene.toml: links.crank.thickness: must be > 0 m, got -0.01"),
    ("thickness = 0.01", 'thickness = "thin"', "links.crank.thickness: must be a finite number m, got 'thin'"),
    ('crank = "crank"', 'crank = "cranck"',
     "scene.toml: mechanisms.main.crank: no link named 'cranck'; links are: coupler, crank, ground, output"),
    ("joints = [[0.0, 0.0], [0.02, 0.0]]", "joints = [[0.0, 0.0]]",
     "mechanisms.main.crank: link 'crank' has 1 joint(s); a crank needs two (O2 -> A): give links.crank at least two"),
    ("joints = [[0.0, 0.0], [0.06, 0.0]]", "joints = [[0.0, 0.0], [6.0, 0.0]]",
     "scene.toml: mechanisms.main: these lengths can never assemble (crank 0.02 m, coupler 0.07 m, output 0.05 m, "
     "ground 6 m): each link must be shorter than the sum of the other three"),
    ('material = "steel"', 'material = "steal"', "links.crank.material: no material named 'steal'; materials are: steel"),
    ("density = 7850.0", "density = 0", "materials.steel.density: must be > 0 kg/m^3, got 0"),
    ("density = 7850.0", "density = 7850.0\npoisson_ratio = 0.7", "materials.steel.poisson_ratio: must lie in (-1, 0.5)"),
    ("density = 7850.0", "young = 1.0", "materials.steel.young: unknown key"),
    ('[links.coupler]\njoints = [[0.0, 0.0], [0.07, 0.0]]', "[links.coupler]\nmass = 1.0",
     "links.coupler.mass: give mass, inertia and center_of_mass together; missing: inertia, center_of_mass"),
    ('[links.coupler]\njoints = [[0.0, 0.0], [0.07, 0.0]]', "[links.coupler]\nthickness = 0.1",
     "links.coupler: give either sketch = \"file.dxf\" or joints = [[x, y], ...] (metres), not both or neither"),
    ("joints = [[0.0, 0.0], [0.07, 0.0]]", "joints = [[0.0, 0.0], [0.07]]", "links.coupler.joints[1]: must be a pair [x, y] m"),
    ("joints = [[0.0, 0.0], [0.07, 0.0]]", 'joints = [[0.0, 0.0], [0.07, 0.0]]\nlayer = "coupler"',
     "links.coupler.layer: only for a sketch link; bare joints are in metres"),
    ('type = "four-bar"', 'type = "fourbar"', "mechanisms.main.type: must be one of 'four-bar', 'slider-crank', 'linkage', got 'fourbar'"),
    ('type = "four-bar"', 'type = "four-bar"\nbranch = "closed"', "mechanisms.main.branch: must be one of 'open', 'crossed'"),
    ('type = "four-bar"', 'type = "four-bar"\noffset_m = 0.01', "mechanisms.main.offset_m: only for type = \"slider-crank\""),
    ('type = "four-bar"', 'type = "four-bar"\nphase_deg = 10.0', "mechanisms.main.phase_deg: only for a loop with driven_by"),
    ('output = "output"', "", "mechanisms.main.output: missing; give the output's link name"),
    ('crank = "crank"', 'crank = {link = "crank", joints = [0, 5]}',
     "mechanisms.main.crank.joints: link 'crank' has joints 0..1, no joint 5"),
    ('crank = "crank"', 'crank = {link = "crank", joints = [0]}', "mechanisms.main.crank.joints: must be [i, j]"),
    ('crank = "crank"', 'crank = {lnk = "crank"}', "mechanisms.main.crank.lnk: unknown key; allowed keys are: link, joints"),
    ('type = "four-bar"', 'type = "four-bar"\ndriven_by = "main"', 'mechanisms.main.driven_by: must be "LOOP.crank" or "LOOP.output"'),
    ("input_speed_rad_s = 10.0", "input_speed_rad_s = [1.0, 2.0]",
     "motion.input_speed_rad_s: give one number, or a list of 36 numbers (one per input angle)"),
    ("input_angle_deg = {start = 0.0, stop = 350.0, num = 36}", "input_angle_deg = {start = 0.0, stop = 350.0}",
     "motion.input_angle_deg.num: missing; give start, stop and num: num angles from start to stop, both included"),
    ("input_angle_deg = {start = 0.0, stop = 350.0, num = 36}", "input_angle_deg = []",
     "motion.input_angle_deg: must be a non-empty list of numbers deg"),
    ("input_angle_deg = {start = 0.0, stop = 350.0, num = 36}\ninput_speed_rad_s = 10.0",
     'input_angle_deg = {expression = "__import__(\'os\')", t = [0.0]}',
     "motion.input_angle_deg.expression: call '__import__' in \"__import__('os')\" is not allowed"),
    ("input_angle_deg = {start = 0.0, stop = 350.0, num = 36}",
     'input_angle_deg = {expression = "90*t", t = [0.0, 1.0]}',
     "motion.input_speed_rad_s: not allowed with an expression: it is the expression's time derivative"),
    ("input_speed_rad_s = 10.0", 'actuator = "coupler"',
     "motion.actuator: link 'coupler' is not a crank, output or slider of any mechanism"),
    ("[motion]", "[loads.couples]\nground = 1.0\n[motion]",
     "loads.couples.ground: no moving link named 'ground' for a couple; moving links are: crank, coupler, output"),
    ("[motion]", "[loads.friction]\npiston = 0.1\n[motion]",
     "loads.friction.piston: no slider named 'piston'; give a slider's link or slider-crank's name: none"),
    ("[motion]", "[loads]\ngravity_m_s2 = [0.0]\n[motion]", "loads.gravity_m_s2: must be a pair [x, y] m/s^2"),
    ("[motion]", "[[loads.forces]]\nlink = \"crank\"\nat_m = [0.0, 0.0]\n[motion]",
     "loads.forces[0].force_n: missing; give [Fx, Fy] in the ground frame, newtons"),
    ("[motion]", "[analysis]\nelement_order = 3\n[motion]", "analysis.element_order: must be 1 (linear) or 2"),
    ("[motion]", "[analysis]\nvalidate = [\"crank\"]\n[motion]",
     "analysis.validate: link 'crank' has bare joints; only links drawn in a sketch can be checked by FEA"),
    ("[motion]", "[analysis]\nstations = 1\n[motion]", "analysis.stations: must be >= 2, got 1"),
    ("[motion]", "[analysis]\nbody_load_near_holes = 1\n[motion]", "analysis.body_load_near_holes: must be true or false, got 1"),
    ("[links.ground]", "[links.spare]\njoints = [[0.0, 0.0], [1.0, 0.0]]\n[links.ground]",
     "links.spare: no mechanism uses this link; name it in a [mechanisms] table or remove it"),
    ("[motion]", "[extra]\n[motion]", "scene.toml: extra: unknown key; allowed keys are: title, notes, units, materials, links,"),
    ("[motion]\ninput_angle_deg = {start = 0.0, stop = 350.0, num = 36}\ninput_speed_rad_s = 10.0\n", "",
     "scene.toml: motion: missing table; add [motion]"),
    ('type = "four-bar"', 'type = "four-bar"\n= oops', "scene.toml: not valid TOML: "),
]


@pytest.mark.parametrize("old, new, message", CASES)
def test_a_wrong_key_is_named_with_what_to_do(tmp_path, old, new, message):
    assert old in BASE
    with pytest.raises(SceneError) as error:
        load(tmp_path, BASE.replace(old, new, 1))
    assert message in str(error.value)
    assert str(error.value).startswith("scene.toml: ") or str(error.value).startswith("scene file")


def test_a_missing_scene_file_is_named(tmp_path):
    with pytest.raises(SceneError, match=r"scene file '.*nowhere.toml' not found"):
        load_scene(tmp_path / "nowhere.toml")


def test_a_sketch_link_names_its_key_when_it_cannot_be_read(tmp_path):
    text = BASE.replace(
        "[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]", '[links.crank]\nsketch = "missing.dxf"'
    )
    with pytest.raises(SceneError) as error:
        load(tmp_path, text)
    message = str(error.value)
    assert message.startswith("scene.toml: links.crank.sketch: ")
    assert "not found" in message


def test_a_sketch_link_needs_a_thickness(tmp_path):
    text = BASE.replace(
        "[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]\nthickness = 0.01",
        '[links.crank]\nsketch = "crank.dxf"',
    )
    with pytest.raises(SceneError, match="links.crank.thickness: missing; a sketch link needs its plate thickness"):
        load(tmp_path, text)


BELL = "joints = [[0.0, 0.0], [0.05, 0.0], [0.0, 0.04]]"
"""A bell crank's three joints: 0 the pivot, 1 and 2 its arms' pins."""


@pytest.mark.parametrize("role, joints", [
    ("crank", "joints = [[0.0, 0.0], [0.02, 0.0]]"),
    ("coupler", "joints = [[0.0, 0.0], [0.07, 0.0]]"),
    ("output", "joints = [[0.0, 0.0], [0.05, 0.0]]"),
])
def test_a_link_with_three_joints_named_bare_in_a_role_is_refused_listing_its_joints(tmp_path, capsys, role, joints):
    # Bare, the name meant joints 0 -> 1: of a bell crank, whichever two pins happen to come first.
    text = BASE.replace(joints, BELL, 1)
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    assert main(["analyze", str(path)]) == 2
    message = capsys.readouterr().err
    assert (
        f"scene.toml: mechanisms.main.{role}: link '{role}' has 3 joints "
        "(0 at (0, 0) m, 1 at (0.05, 0) m, 2 at (0, 0.04) m;"
    ) in message
    assert f'give them: {role} = {{link = "{role}", joints = [i, j]}}' in message
    fixed = text.replace(f'{role} = "{role}"', f'{role} = {{link = "{role}", joints = [0, 2]}}', 1)
    assert load(tmp_path, fixed).machine.loops[0].roles[role].joints == (0, 2)


def write_bell_sketch(path) -> None:
    """A bell crank drawn in mm: pivot O4 at (0, 0), arm pins B at (60, 50) and C at (40, -60).
    Joints are numbered by x, then y: 0 O4, 1 C, 2 B, so "joints 0 -> 1" is O4 -> C, not O4 -> B."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-10, -10), (30, -70), (50, -70), (70, 60), (50, 60), (-10, 10)], close=True,
                       dxfattribs={"layer": "bell"})
    for point in ((0, 0), (60, 50), (40, -60)):
        msp.add_point(point, dxfattribs={"layer": "bell"})
    doc.saveas(path)


def test_a_sketched_bell_crank_named_bare_as_output_exits_2_naming_its_sorted_joints(tmp_path, capsys):
    write_bell_sketch(tmp_path / "bell.dxf")
    text = BASE.replace(
        '[links.output]\njoints = [[0.0, 0.0], [0.05, 0.0]]',
        '[links.output]\nsketch = "bell.dxf"\nlayer = "bell"\nthickness = 0.005',
    )
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    out = tmp_path / "out.json"
    assert main(["analyze", str(path), "--json", str(out)]) == 2
    message = capsys.readouterr().err
    assert message.count("\n") == 1 and not out.exists()
    assert (
        "mechanisms.main.output: link 'output' has 3 joints (0 at (0, 0) m, 1 at (0.04, -0.06) m, "
        "2 at (0.06, 0.05) m; numbered as given: a sketch's by x, then y)"
    ) in message


def write_crank_sketch(path, upright: bool = False) -> None:
    """The base scene's crank drawn in mm: a 40 x 16 bar, joints (0, 0) and (20, 0) in 6 mm pin holes
    (``upright``: turned 90 degrees counter-clockwise, joints (0, 0) and (0, 20))."""
    def turn(x, y):
        return (-y, x) if upright else (x, y)

    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    corners = [turn(*c) for c in ((-10, -8), (30, -8), (30, 8), (-10, 8))]
    msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": "crank"})
    for x in (0, 20):
        msp.add_circle(turn(x, 0), 3, dxfattribs={"layer": "crank"})
        msp.add_point(turn(x, 0), dxfattribs={"layer": "crank"})
    doc.saveas(path)


def crank_force_scene(tmp_path, at_m: str, upright: bool = False):
    write_crank_sketch(tmp_path / "crank.dxf", upright)
    text = BASE.replace(
        '[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]', '[links.crank]\nsketch = "crank.dxf"\nlayer = "crank"',
    ) + f'\n[[loads.forces]]\nlink = "crank"\nat_m = {at_m}\nforce_n = [0.0, -50.0]\n'
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    return path


@pytest.mark.parametrize("upright", [False, True], ids=["drawn along x", "drawn along y"])
def test_a_force_10_mm_outside_its_link_exits_2_with_the_distance_and_writes_nothing(tmp_path, capsys, upright):
    # The bar's top edge is at y = 8 mm in the crank's member frame (origin at joint 0, +x to joint 1),
    # however the sketch turns it.
    path = crank_force_scene(tmp_path, "[0.01, 0.018]", upright)
    out = tmp_path / "out.json"
    assert main(["analyze", str(path), "--json", str(out)]) == 2
    message = capsys.readouterr().err
    assert message.count("\n") == 1 and not out.exists()
    assert message.startswith(
        "linkstress: error: scene.toml: loads.forces[0].at_m: [0.01, 0.018] m is 0.01 m outside the outline of "
        "link 'crank' (member frame: origin at joint 0, +x toward joint 1);"
    )
    assert "put at_m in its material, or in a pin hole" in message


@pytest.mark.parametrize("at_m, where", [
    ("[0.01, 0.008]", "on the top edge"),
    ("[0.02, 0.0]", "at the centre of joint 1's pin hole"),
    ("[0.021, -0.002]", "in joint 1's pin hole, off its centre"),
    ("[0.01, 0.0]", "in material"),
])
@pytest.mark.parametrize("upright", [False, True], ids=["drawn along x", "drawn along y"])
def test_a_force_on_its_link_is_read(tmp_path, at_m, where, upright):
    scene = load_scene(crank_force_scene(tmp_path, at_m, upright))
    assert scene.loads.forces[0].link == "crank", where


@pytest.mark.parametrize("members, message", [
    ("[[0, 1], [1, 0]]", "links.crank.members: link 'crank': members [(0, 1), (1, 0)] close a loop at member [1, 0]; give a tree"),
    ("[[0, 2]]", "links.crank.members: link 'crank': member [0, 2] must join two different joints among 0..1"),
    ("[0, 1]", "links.crank.members: must be a list of joint pairs [[i, j], ...] (joint indices, integers)"),
    ('[["a", 1]]', "links.crank.members: must be a list of joint pairs [[i, j], ...] (joint indices, integers)"),
])
def test_wrong_members_of_a_sketch_link_exit_2_naming_the_key(tmp_path, capsys, members, message):
    path = crank_force_scene(tmp_path, "[0.01, 0.0]")
    path.write_text(path.read_text().replace('layer = "crank"', f'layer = "crank"\nmembers = {members}', 1))
    out = tmp_path / "out.json"
    assert main(["analyze", str(path), "--json", str(out)]) == 2
    error = capsys.readouterr().err
    assert message in error and error.count("\n") == 1 and not out.exists()


def test_members_of_a_bare_joints_link_are_refused(tmp_path):
    with pytest.raises(SceneError, match="links.coupler.members: only for a sketch link"):
        load(tmp_path, BASE.replace("[links.coupler]\n", "[links.coupler]\nmembers = [[0, 1]]\n"))


def test_members_named_in_a_scene_are_the_ones_analysed(tmp_path):
    path = crank_force_scene(tmp_path, "[0.01, 0.0]")
    path.write_text(path.read_text().replace('layer = "crank"', 'layer = "crank"\nmembers = [[1, 0]]', 1))
    crank = load_scene(path).links["crank"]
    assert crank.members == ((1, 0),)
    (member,) = link_members(crank.profile, crank.frame_joints, crank.members)
    assert member.joints == (1, 0)


FATIGUE = """density = 7850.0
yield_strength = 350e6
endurance_limit = 250e6
ultimate_strength = 500e6
surface_factor = 0.8
size_factor = 0.9"""
"""A steel with every fatigue key: S_e' 250 MPa, S_ut 500 MPa, k_a 0.8, k_b 0.9."""


def test_a_material_with_every_fatigue_key_reads_them_in_pascals(tmp_path):
    steel = load(tmp_path, BASE.replace("density = 7850.0", FATIGUE, 1)).materials["steel"]
    strength = steel.fatigue_strength
    assert (strength.endurance_limit, strength.ultimate_strength, strength.yield_strength) == (250e6, 500e6, 350e6)
    assert (strength.surface_factor, strength.size_factor) == (0.8, 0.9)
    assert strength.corrected_endurance_limit == pytest.approx(180e6, rel=1e-15)


def test_a_material_without_fatigue_keys_has_no_fatigue_strength_and_unit_marin_factors(tmp_path):
    steel = load(tmp_path, BASE).materials["steel"]
    assert steel.fatigue_strength is None
    assert (steel.surface_factor, steel.size_factor) == (1.0, 1.0)


@pytest.mark.parametrize("old, new, message", [
    ("endurance_limit = 250e6", "endurance_limit = -250e6", "materials.steel.endurance_limit: must be > 0 Pa, got -250000000.0"),
    ("ultimate_strength = 500e6", "ultimate_strength = 5e14",
     "materials.steel.ultimate_strength: must be at most 1e+13 Pa in size (a modulus or strength; check the unit), "
     "got 500000000000000.0"),
    ("surface_factor = 0.8", "surface_factor = 0", "materials.steel.surface_factor: must be > 0, got 0"),
    ("size_factor = 0.9", "size_factor = 2.0", "materials.steel.size_factor: must lie in (0, 1.5] (a Marin factor), got 2.0"),
    ("surface_factor = 0.8", "surface_factor = 80", "materials.steel.surface_factor: must lie in (0, 1.5] (a Marin factor), got 80.0"),
    ("size_factor = 0.9", 'size_factor = "0.9"', "materials.steel.size_factor: must be a finite number, got '0.9'"),
    ("endurance_limit = 250e6", "endurance_limit = 500e6",
     "materials.steel.endurance_limit: must be below ultimate_strength (500000000.0 Pa), got 500000000.0"),
    ("yield_strength = 350e6", "yield_strength = 600e6",
     "materials.steel.yield_strength: must not exceed ultimate_strength (500000000.0 Pa), got 600000000.0"),
    ("endurance_limit = 250e6\nultimate_strength = 500e6\n", "",
     "materials.steel.surface_factor: fatigue needs endurance_limit and ultimate_strength together [Pa]; "
     "missing: endurance_limit, ultimate_strength"),
    ("ultimate_strength = 500e6\n", "",
     "materials.steel.endurance_limit: fatigue needs endurance_limit and ultimate_strength together [Pa]; "
     "missing: ultimate_strength"),
    ("endurance_limit = 250e6\n", "",
     "materials.steel.ultimate_strength: fatigue needs endurance_limit and ultimate_strength together [Pa]; "
     "missing: endurance_limit"),
])
def test_a_wrong_fatigue_key_exits_2_with_one_message_naming_it(tmp_path, capsys, old, new, message):
    assert old in FATIGUE
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(BASE.replace("density = 7850.0", FATIGUE.replace(old, new, 1), 1)))
    out = tmp_path / "out.json"
    assert main(["analyze", str(path), "--json", str(out)]) == 2
    error = capsys.readouterr().err
    assert error == f"linkstress: error: scene.toml: {message}\n" and not out.exists()
