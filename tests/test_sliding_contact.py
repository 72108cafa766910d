"""A slider's block pushes on the link it slides along (a guide) where the block is, a point that
moves along the guide: the section forces take the push there, exactly, at every position; the
guide is stressed like any link, on its beam sections, and its verdict says that the FEA cannot
take it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.dynamics.internal_forces import internal_forces
from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase, SlidingContact
from linkstress.materials import Material
from linkstress.model_choice import FEA_PEAKS, NO_FEA
from linkstress.scene import load_scene

STEEL = Material("steel", 7850.0, 200e9, 0.3)
SHAPER = Path(__file__).resolve().parents[1] / "validation" / "cases" / "whitworth_shaper" / "scene.toml"


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


def test_the_guide_has_a_beam_row_that_says_the_fea_cannot_take_it(tmp_path, capsys):
    out = tmp_path / "shaper.json"
    assert main(["analyze", str(SHAPER), "--peaks", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    lever = next(row for row in data["verdict"]["rows"] if row["link"] == "lever")
    assert lever["governing"] == "beam nominal" and lever["trust"] == "beam only"
    assert "the FEA cannot take it" in lever["trust_reason"]
    assert data["links"]["lever"]["model"] == FEA_PEAKS
    assert NO_FEA + "the block's contact moves along the link" in data["links"]["lever"]["model_reason"]
    assert "peak_max_von_mises_pa" not in data["links"]["lever"]
    assert [entry["link"] for entry in data["verdict"]["not_analysed"]] == ["collar", "ram"]
    assert "the FEA cannot take lever" in text


def test_no_fea_is_run_on_a_guide_and_the_fea_refuses_a_sliding_contact():
    """By default every stressed link is validated, but not a guide; the FEA itself refuses a load
    case with a sliding contact rather than drop the push."""
    from linkstress.validation.fea.errors import FEAError
    from linkstress.validation.fea.loads import check_load_case

    scene = load_scene(SHAPER)
    plan = plan_for(scene)
    assert "lever" in plan.stresses and "lever" not in plan.validate and "lever" not in plan.with_peaks().peaks
    bar = straight_bar(1.0, 0.05, 0.05, 0.01, STEEL, hole_diameter=0.01)
    with pytest.raises(FEAError, match="a slider's block slides along it"):
        check_load_case(bar, pushed_bar(np.array([0.3])))
