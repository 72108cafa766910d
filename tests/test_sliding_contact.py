"""A slider's block pushes on the link it slides along (a guide) where the block is, a point that
moves along the guide: the section forces take the push there, exactly, at every position; the
guide is stressed like any link, on its beam sections, and its verdict says that the FEA cannot
take it."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.dynamics.internal_forces import internal_forces
from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase, SlidingContact, contact_hole
from linkstress.materials import Material
from linkstress.model_choice import FEA_PEAKS, NO_FEA
from linkstress.scene import load_scene

STEEL = Material("steel", 7850.0, 200e9, 0.3)
CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
SHAPER = CASES / "whitworth_shaper" / "scene.toml"
LOADER = CASES / "loader_arm_cylinder" / "scene.toml"


def pushed_bar(contact_x: np.ndarray, push: float = 10.0, couple: float = 2.0) -> LinkLoadCase:
    """A weightless, still bar (joints at x = 0 and 1 m) pushed across by a block at ``contact_x``
    (P,) [m] with ``push`` [N] along +y and a ``couple`` [N m], held by its two pins: about joint 0,
    R1_y = -(couple + a push) and R0_y = -push - R1_y."""
    count = len(contact_x)
    r1 = -(couple + contact_x * push)
    pins = np.zeros((count, 2, 2))
    pins[:, 0, 1], pins[:, 1, 1] = -push - r1, r1
    contact = SlidingContact(np.column_stack([contact_x, np.zeros(count)]), np.tile([0.0, push], (count, 1)),
                             np.full(count, couple), anchor=0)
    zeros = np.zeros(count)
    return LinkLoadCase((0, 1), pins, np.zeros((count, 2)), zeros, zeros, np.zeros((count, 2)), np.zeros((count, 2)),
                        contacts=(contact,))


def closed_form(x: np.ndarray, a: float, push: float = 10.0, couple: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """V, M of ``pushed_bar`` at ``x`` (left free body, V = -F_L,y, M = M_L about the cut): left of
    the block only joint 0's R0_y; right of it the push and its couple too."""
    r0 = -push + (couple + a * push)
    past = x > a
    shear = -(r0 + past * push)
    moment = -x * r0 + past * ((a - x) * push + couple)
    return shear, moment


@pytest.mark.parametrize("where", ["straight sections", "member sections"])
def test_the_push_enters_the_sections_where_the_block_is_at_every_position(where):
    a = np.array([0.3, 0.7, 0.05])
    loads = pushed_bar(a)
    bar = straight_bar(1.0, 0.05, 0.05, 0.01, STEEL)
    x = np.linspace(0.0, 1.0, 41) + 0.0125  # no station on a block
    x = x[x < 1.0]
    if where == "straight sections":
        forces = internal_forces(bar, loads, bar.sections(x))
    else:
        forces = section_stresses(bar, loads, x).forces
    for k, at in enumerate(a):
        shear, moment = closed_form(x, at)
        np.testing.assert_allclose(forces.shear[k], shear, atol=1e-9)
        np.testing.assert_allclose(forces.moment[k], moment, atol=1e-9)
    np.testing.assert_allclose(forces.normal, 0.0, atol=1e-9)
    assert (forces.mismatch < 1e-12).all()


def test_a_contact_keeps_the_link_in_equilibrium_with_its_pins():
    loads = pushed_bar(np.array([0.3, 0.7]))
    force, moment = loads.residual_of(0.0, 0.0, np.zeros(2), np.array([[0.0, 0.0], [1.0, 0.0]]))
    np.testing.assert_allclose(force, 0.0, atol=1e-12)
    np.testing.assert_allclose(moment, 0.0, atol=1e-12)
    sliced = loads.at(np.array([1]))
    assert sliced.contacts[0].at[0, 0] == 0.7 and sliced.contacts[0].couple.shape == (1,)


def test_the_shapers_slotted_lever_is_in_equilibrium_with_the_collars_push_where_the_collar_is():
    scene = load_scene(SHAPER)
    result = run_analysis(scene)
    loads = result.forces.link_loads["lever"]
    (contact,) = loads.contacts
    force, moment = loads.residual(scene.links["lever"].profile)
    scale = np.abs(loads.pin_forces).max()
    assert np.abs(force).max() < 1e-9 * scale and np.abs(moment).max() < 1e-9 * scale
    # The collar rides on the lever's line (joints 0 -> 1, the member frame's x axis), inside its
    # slot, between O4 (x = 0) and T (0.56 m).
    np.testing.assert_allclose(contact.at[:, 1], 0.0, atol=1e-12)
    assert (contact.at[:, 0] > 0).all() and (contact.at[:, 0] < 0.56).all()
    assert result.stresses["lever"].mismatch.max() < 1e-9


def test_a_guide_whose_contact_runs_in_its_material_has_a_beam_row_that_says_the_fea_cannot_take_it(tmp_path, capsys):
    """The loader's barrel is drawn as a plate: the rod's piston runs inside its material, not in a
    slot, so the FEA has no wall to bear it on; --peaks leaves it on its beam sections and says so."""
    out = tmp_path / "loader.json"
    assert main(["analyze", str(LOADER), "--peaks", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    barrel = next(row for row in data["verdict"]["rows"] if row["link"] == "barrel")
    assert barrel["governing"] == "beam nominal" and barrel["trust"] == "beam only"
    assert "the FEA cannot take it" in barrel["trust_reason"]
    assert data["links"]["barrel"]["model"] == FEA_PEAKS
    assert NO_FEA + "the block's contact is not inside a closed slot of the link" in data["links"]["barrel"]["model_reason"]
    assert "peak_max_von_mises_pa" not in data["links"]["barrel"]
    assert "peak_max_von_mises_pa" in data["links"]["arm"]
    assert "the FEA cannot take barrel" in text


def test_the_fea_refuses_a_contact_outside_a_closed_slot_rather_than_drop_it():
    from linkstress.validation.fea.errors import FEAError
    from linkstress.validation.fea.loads import check_load_case

    bar = straight_bar(1.0, 0.05, 0.05, 0.01, STEEL, hole_diameter=0.01)
    with pytest.raises(FEAError, match="not inside a closed slot"):
        check_load_case(bar, pushed_bar(np.array([0.3])))


def test_validate_compares_the_slotted_lever_and_leaves_out_the_barrel_saying_why(tmp_path, capsys):
    """The shaper's lever is validated like any link (its cuts all cross the slot or lie beside a
    pin, so none is compared; its peak and convergence study are). The loader's barrel has no slot
    for the FEA to bear the rod on: validate leaves it out, says why, and passes."""
    shaper, loader = tmp_path / "shaper.json", tmp_path / "loader.json"
    assert main(["validate", str(SHAPER), "--positions", "2", "--json", str(shaper)]) == 0
    lever = json.loads(shaper.read_text())["links"]["lever"]
    assert lever["fea_max_von_mises_pa"] > 3 * lever["beam_max_von_mises_pa"]
    assert main(["validate", str(LOADER), "--positions", "2", "--json", str(loader)]) == 0
    text = capsys.readouterr().out
    data = json.loads(loader.read_text())
    assert list(data["links"]) == ["arm"]
    assert data["not_validated"] == [{"link": "barrel", "reason": "a slider's block slides along it outside a closed "
                                                                "slot of it: no FEA bears it"}]
    assert "not validated: barrel (" in text


@pytest.fixture(scope="module")
def shaper_lever():
    """The shaper's lever, its loads over the sweep and its peak mesh (the FEA imported here)."""
    from linkstress.validation.peaks import peak_mesh

    scene = load_scene(SHAPER)
    result = run_analysis(scene, replace(plan_for(scene), beam_only=True))
    profile = scene.links["lever"].profile
    loads = result.forces.link_loads["lever"]
    return profile, loads, peak_mesh(profile, loads.frame_joints), result


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_block_bears_on_the_slot_wall_it_pushes_over_its_length_with_the_contacts_force_and_couple(shaper_lever, sign):
    from linkstress.validation.fea.link import link_model
    from linkstress.validation.fea.loads import contact_loads, nodal_resultant

    profile, loads, mesh, _ = shaper_lever
    at = loads.at(np.array([29]))
    contact = at.contacts[0]
    pushed = SlidingContact(contact.at, sign * contact.force, np.array([25.0]), contact.anchor, contact.length)
    model = link_model(profile, at, mesh)
    hole = contact_hole(profile.local_outline(*loads.frame_joints), pushed)
    forces = contact_loads(model, model.plane.holes[hole], pushed, np.zeros(2), mesh.station_size)
    force, moment = nodal_resultant(model, forces, about=pushed.at[0])
    np.testing.assert_allclose(force[0], pushed.force[0], atol=1e-9 * np.abs(pushed.force).max())
    assert moment[0] == pytest.approx(25.0, abs=1e-9 * np.abs(pushed.force).max())
    xy = model.scalar.doflocs
    loaded = np.hypot(forces[model.components[0], 0], forces[model.components[1], 0]) > 0
    # The collar is 70 mm long (the nodes of an edge it reaches into are loaded); the slot's walls are
    # 18 mm either side of the lever's axis.
    assert np.abs(xy[0, loaded] - pushed.at[0, 0]).max() <= 0.035 + mesh.hole_size
    np.testing.assert_allclose(xy[1, loaded], 0.018 * np.sign(pushed.force[0, 1]), atol=1e-9)


def test_the_direct_peaks_are_the_direct_fea_at_each_position(shaper_lever):
    from linkstress.validation.direct_peaks import direct_sweep_peaks
    from linkstress.validation.fea.link import solve_link

    profile, loads, mesh, _ = shaper_lever
    positions = np.array([3, 29])
    peaks = direct_sweep_peaks(profile, loads, positions, mesh)
    direct = solve_link(profile, loads.at(positions), mesh)
    np.testing.assert_allclose(peaks.peak, direct.von_mises_peak, rtol=1e-9)
    assert peaks.cases.count == 0 and (peaks.reaction_ratio < 1e-6).all()  # the loads balance: the supports carry ~nothing


def test_the_slotted_levers_fea_finds_the_ligaments_bending_that_its_beam_sections_miss(tmp_path, capsys):
    """The collar pushes one ligament of the slot (8.3 kN at 290 deg, 59 mm from the slot's near
    end, 300 mm between its ends): the ligament bends between the slot's ends, about P a b / L =
    393 N m on a 25 x 27 mm section, 129 MPa, where the whole section's beam theory gives 43 MPa at
    most. The FEA, a direct solve per position, governs the lever's verdict."""
    out = tmp_path / "shaper.json"
    assert main(["analyze", str(SHAPER), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    lever = next(row for row in data["verdict"]["rows"] if row["link"] == "lever")
    record = data["links"]["lever"]
    assert lever["governing"] == "FEA peak" and lever["trust"] == "FEA"
    assert record["peak_mesh"]["direct_solves"] == 36 and record["peak_mesh"]["unit_load_cases"] == 0
    assert record["peak_max_von_mises_pa"] > 3 * record["beam_max_von_mises_pa"]
    assert lever["stress_pa"] == pytest.approx(record["peak_max_von_mises_pa"])
    assert "a slider's block slides in its slot" in record["model_reason"] and NO_FEA not in record["model_reason"]
    assert "lever" in text


def test_a_block_drawn_without_a_link_bears_over_the_slots_width_and_its_peak_converges(tmp_path):
    """The shaper with its collar left out (a massless block in the slot) and friction 0.15 on it:
    the block bears over the slot's 36 mm width, not on a point of the wall, so the lever's peak
    settles on the mesh as with the drawn 70 mm collar."""
    for sketch in SHAPER.parent.glob("*.dxf"):
        (tmp_path / sketch.name).write_bytes(sketch.read_bytes())
    text = SHAPER.read_text()
    start = text.index("[links.collar]")
    text = text[:start] + text[text.index("[links.lever]"):]
    text = text.replace(', block = "collar"}', "}") + '\n[loads.friction]\n"crank:1" = 0.15\n'
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--no-cache", "--json", str(out)]) == 0
    lever = json.loads(out.read_text())["links"]["lever"]
    assert lever["peak_converged"] and lever["peak_mesh"]["direct_solves"] == 36
    assert 150e6 < lever["peak_max_von_mises_pa"] < 220e6
