"""A scene value that real links and materials do not have is warned of in ``Scene.warnings``, one line
naming the key and the unit it looks like written in; the scene still loads.

The ranges (docs/scenes.md, "Plausible values"): plate thickness 0.1 mm to 300 mm; density 100 to
25,000 kg/m^3 (balsa wood about 150, osmium 22,590); Young's modulus 0.1 GPa to 1,200 GPa (LDPE
about 0.2 GPa, diamond 1,050 GPa); yield, endurance and ultimate strengths 1 MPa to 5 GPa. The unit
sizes are exact by definition: 1 in = 25.4 mm, 1 lb = 0.45359237 kg, 1 psi = 1 lbf/in^2 =
6894.757293168 Pa (NIST SP 811, appendix B).
"""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import ezdxf
import pytest

from linkstress.cli import main
from linkstress.scene import load_scene
from linkstress.scene.plausibility import GYRATION_FACTOR, RULES

FOURBAR = """
[materials.steel]
density = 7850.0
{material}

[links.crank]
joints = [[0.0, 0.0], [0.1, 0.0]]
mass = 0.5
inertia = 0.001
center_of_mass = [0.05, 0.0]
{crank}

[links.coupler]
joints = [[0.0, 0.0], [0.3, 0.0]]
mass = 1.0
inertia = 0.01
center_of_mass = [0.15, 0.0]

[links.output]
joints = [[0.0, 0.0], [0.25, 0.0]]
mass = 0.8
inertia = 0.005
center_of_mass = [0.125, 0.0]

[links.ground]
joints = [[0.0, 0.0], [0.3, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = 30.0
"""


def warnings_of(tmp_path: Path, material: str = "", crank: str = "", text: str | None = None) -> tuple[str, ...]:
    """The warnings of the bare-joint four-bar with ``material`` lines added to [materials.steel]
    (which replace its density when they give one) and ``crank`` lines to [links.crank]."""
    scene = text if text is not None else FOURBAR.format(material=material, crank=crank)
    if "density" in material:
        scene = scene.replace("density = 7850.0\n", "", 1)
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(scene))
    return load_scene(path).warnings


def test_a_real_machine_has_no_warnings(tmp_path):
    material = "youngs_modulus = 200e9\nyield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6"
    assert warnings_of(tmp_path, material, "thickness = 0.006\nmaterial = \"steel\"") == ()


def test_every_shipped_scene_has_no_warnings():
    # the cases and the tutorial are real designs: a warning there would be a false alarm
    repo = Path(__file__).resolve().parents[1]
    scenes = sorted(repo.glob("validation/cases/*/scene.toml")) + sorted(repo.glob("docs/**/*.toml"))
    assert len(scenes) >= 7
    for path in scenes:
        assert load_scene(path).warnings == (), path


# Each key: (a valid companion table line or "", the key's low bound, its high bound). The strengths
# of fatigue come in pairs: the endurance limit must stay below the ultimate strength.
BOUNDS = {
    "density": 100.0, "youngs_modulus": 1e8, "yield_strength": 1e6, "endurance_limit": 1e6, "ultimate_strength": 1e6,
}


def material_lines(key: str, value: float) -> str:
    """[materials.steel] lines giving ``key`` = ``value`` and whatever fatigue needs beside it."""
    line = f"{key} = {value!r}"
    if key == "endurance_limit":
        return f"{line}\nultimate_strength = {max(2 * value, 400e6)!r}"
    if key == "ultimate_strength":
        return f"{line}\nendurance_limit = {0.5 * value!r}"
    return line


@pytest.mark.parametrize("key", list(BOUNDS))
@pytest.mark.parametrize("side", ["low", "high"])
def test_a_material_value_just_outside_its_range_is_warned_and_one_on_the_bound_is_not(tmp_path, key, side):
    rule = RULES[key]
    bound = rule.low if side == "low" else rule.high
    outside = bound * (0.999 if side == "low" else 1.001)
    on_bound = warnings_of(tmp_path, material_lines(key, bound))
    assert not [w for w in on_bound if w.startswith(f"materials.steel.{key} ")], on_bound
    warned = [w for w in warnings_of(tmp_path, material_lines(key, outside)) if w.startswith(f"materials.steel.{key} ")]
    assert len(warned) == 1, warned
    assert warned[0].startswith(f"materials.steel.{key} = {outside:g} {rule.unit}: ")
    assert f"real {rule.span}" in warned[0]


@pytest.mark.parametrize("side", ["low", "high"])
def test_a_thickness_just_outside_0_1_mm_to_300_mm_is_warned_and_one_on_the_bound_is_not(tmp_path, side):
    bound = 1e-4 if side == "low" else 0.3
    outside = bound * (0.999 if side == "low" else 1.001)
    assert warnings_of(tmp_path, crank=f"thickness = {bound!r}") == ()
    (warned,) = warnings_of(tmp_path, crank=f"thickness = {outside!r}")
    assert warned.startswith(f"links.crank.thickness = {outside:g} m: ")


@pytest.mark.parametrize(
    ("key", "value", "meant", "si"),
    [
        # 6 mm = 6 x 1e-3 m; the brief's own two slips
        ("thickness", 6, "6 mm", 0.006),
        ("yield_strength", 250, "250 MPa", 250e6),
        # 7.85 g/cm^3 = 7.85 x 1000 kg/m^3 (steel)
        ("density", 7.85, "7.85 g/cm^3", 7850.0),
        # 0.1 lb/in^3 = 0.1 x 0.45359237 / 0.0254^3 kg/m^3 (aluminium, 2768 kg/m^3)
        ("density", 0.1, "0.1 lb/in^3", 0.1 * 0.45359237 / 0.0254**3),
        # specific weight 77,000 N/m^3 / g = 7852 kg/m^3
        ("density", 77_000, "77000 N/m^3 (a weight per volume)", 77_000 / 9.80665),
        ("youngs_modulus", 200, "200 GPa", 200e9),
        ("youngs_modulus", 70_000, "70000 MPa", 70e9),
        # 30e6 psi, the modulus of steel in US tables: 30e6 x 6894.757 Pa = 206.8 GPa
        ("youngs_modulus", 30e6, "3e+07 psi", 30e6 * 6894.757293168361),
        # 36 ksi (A36 steel's yield): 36 x 6.894757e6 Pa; 36 MPa fits too and comes first
        ("yield_strength", 36, "36 ksi", 36 * 6894.757293168361e3),
        ("ultimate_strength", 58_000, "58000 psi", 58_000 * 6894.757293168361),
        ("endurance_limit", 200_000, "200000 kPa", 200e6),
    ],
)
def test_the_warning_names_the_unit_the_value_looks_written_in_and_its_si_value(tmp_path, key, value, meant, si):
    if key == "thickness":
        found = warnings_of(tmp_path, crank=f"thickness = {value!r}")
    elif key in ("endurance_limit", "ultimate_strength"):
        found = warnings_of(tmp_path, material_lines(key, value))
    else:
        found = warnings_of(tmp_path, f"{key} = {value!r}")
    (warning,) = [w for w in found if f".{key} = " in w]
    suggested = dict(re.findall(r"(?:did you mean |or )(\S+ [^=?]+?) = ([-+.\de]+)", warning))
    assert meant in suggested, warning
    assert float(suggested[meant]) == pytest.approx(si, rel=5e-4)
    assert len(warning) < 200 and "\n" not in warning


def test_a_value_no_unit_explains_is_warned_without_a_guess(tmp_path):
    # 9 GPa: stronger than any steel, and no unit of the table (each larger than a Pa) brings it down
    (warning,) = warnings_of(tmp_path, "yield_strength = 9e9")
    assert warning == (
        "materials.steel.yield_strength = 9e+09 Pa: real strengths are 1 MPa to 5 GPa, soft polymers to the "
        "strongest steels; check the value and its unit"
    )


def test_a_value_warned_of_still_loads_and_keeps_its_value(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(FOURBAR.format(material="yield_strength = 250", crank=""))
    scene = load_scene(path)
    assert scene.materials["steel"].yield_strength == 250.0
    assert len(scene.warnings) == 1


def test_each_value_gets_one_line_in_the_scene_s_order(tmp_path):
    material = "youngs_modulus = 200\nyield_strength = 250"
    found = warnings_of(tmp_path, material.replace("youngs", "density = 7.85\nyoungs"), "thickness = 6")
    assert [w.split(" = ")[0] for w in found] == [
        "materials.steel.density", "materials.steel.youngs_modulus", "materials.steel.yield_strength",
        "links.crank.thickness",
    ]


# --- values against the link's own size --------------------------------------------------------------


def draw_bar(path: Path, length: float = 0.1, height: float = 0.02) -> Path:
    """A bar ``length`` between its two pin holes (metres), square ends ``height`` / 2 past them."""
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    h = height / 2
    msp.add_lwpolyline([(-h, -h), (length + h, -h), (length + h, h), (-h, h)], close=True)
    for x in (0.0, length):
        msp.add_circle((x, 0.0), height / 4)
        msp.add_point((x, 0.0))
    doc.saveas(path)
    return path


def drawn_crank(tmp_path: Path, thickness: float) -> str:
    draw_bar(tmp_path / "crank.dxf")
    crank = f'[links.crank]\nsketch = "crank.dxf"\nthickness = {thickness!r}\nmaterial = "steel"\n'
    start = FOURBAR.index("[links.crank]")
    end = FOURBAR.index("[links.coupler]")
    return FOURBAR[:start].format(material="") + crank + "\n" + FOURBAR[end:]


def test_a_plate_thicker_than_its_drawn_link_is_long_is_warned_as_a_block(tmp_path):
    # the bar is 0.12 m by 0.02 m: its outline's diagonal is sqrt(0.12^2 + 0.02^2) = 0.1217 m.
    # 0.25 (meant inches) is inside 0.1-300 mm yet twice the link: 0.25 mm and 0.25 in = 6.35 mm fit
    (warning,) = warnings_of(tmp_path, text=drawn_crank(tmp_path, 0.25))
    assert warning.startswith("links.crank.thickness = 0.25 m is more than the link's size, 0.1217 m: a block")
    assert "did you mean 0.25 mm = 250e-6 or 0.25 in = 0.00635?" in warning
    assert warnings_of(tmp_path, text=drawn_crank(tmp_path, 0.12)) == ()


def test_an_inertia_in_cad_units_is_warned_by_its_radius_of_gyration(tmp_path):
    # crank: mass 0.5 kg, size 0.1 m (its joints). 1000 (kg mm^2 meant) gives sqrt(1000 / 0.5) = 44.7 m,
    # 447 times the crank; 1000 kg mm^2 = 1e-3 kg m^2 and 1000 g mm^2 = 1e-6 kg m^2
    text = FOURBAR.format(material="", crank="").replace("inertia = 0.001", "inertia = 1000.0", 1)
    (warning,) = warnings_of(tmp_path, text=text)
    assert warning == (
        "links.crank.inertia = 1000 kg m^2 with mass = 0.5 kg is a radius of gyration of 44.72 m, over 100 times the "
        "link's size 0.1 m: is it in kg mm^2 (= 0.001) or g mm^2 (= 1e-6)?"
    )


@pytest.mark.parametrize("factor, warned", [(0.999, False), (1.001, True)])
def test_the_radius_of_gyration_bound_is_100_link_sizes(tmp_path, factor, warned):
    # a radius of gyration k = factor x 100 x 0.1 m: inertia = m k^2 with m = 0.5 kg
    inertia = 0.5 * (factor * GYRATION_FACTOR * 0.1) ** 2
    text = FOURBAR.format(material="", crank="").replace("inertia = 0.001", f"inertia = {inertia!r}", 1)
    assert bool(warnings_of(tmp_path, text=text)) is warned


def test_a_fatigue_refusal_caused_by_a_unit_slip_names_the_slip(tmp_path, capsys):
    # ultimate_strength = 58 (ksi meant: 58 x 6.894757e6 = 399.9e6 Pa) puts the real 200 MPa endurance
    # limit above it: refused, and the refusal says which value looks like a slip
    path = tmp_path / "scene.toml"
    path.write_text(FOURBAR.format(material="endurance_limit = 200e6\nultimate_strength = 58", crank=""))
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert "materials.steel.endurance_limit: must be below ultimate_strength (58.0 Pa), got 200000000.0; " in err
    assert "materials.steel.ultimate_strength = 58 Pa: did you mean 58 MPa = 58e6 or 58 ksi = 399.9e6?" in err
    assert len(err.strip().splitlines()) == 1


def test_the_warnings_docs_scenes_md_shows_are_the_readers(tmp_path):
    doc = (Path(__file__).resolve().parents[1] / "docs" / "scenes.md").read_text()
    shown = [line.strip() for line in doc.splitlines() if line.startswith("    ") and ": did you mean " in line]
    computed = warnings_of(tmp_path, "yield_strength = 250", "thickness = 6")
    assert sorted(shown) == sorted(computed)
