"""Simulation.step: the brush's physics from Python (Baxter & Lin 2004, §3)."""
import numpy as np
import pytest

import bristle

# The paper's push on a brush pressed 5 mm must be clearly upward: the
# round's spines bend at 0.8-30 N mm/rad (round.json), so any press of
# millimetres holds them at least millinewtons. 1 mN is far below that and
# far above the solver's noise.
MIN_PRESS_FORCE_N = 1e-3


def lowered(sim, x, y, top_z, bottom_z, step_mm=0.25, dt_s=0.01):
    """Lowers the upright ferrule from top_z to bottom_z in steps of step_mm."""
    state = sim.reset([x, y, top_z])
    n = int(round((top_z - bottom_z) / step_mm))
    for k in range(1, n + 1):
        state = sim.step([x, y, top_z - step_mm * k], t_s=dt_s * k)
    return state


def test_in_the_air_nothing_touches(round_brush):
    sim = bristle.Simulation(round_brush)
    top = round_brush.hair_length_mm + 3
    s = lowered(sim, 10, 10, top, top - 2)
    assert s.contact_joints == 0 and not s.in_contact and not s.contact.any()
    assert np.allclose(s.force_n, 0) and np.allclose(s.spine_force_n, 0)
    assert s.joints_mm.shape[0] == round_brush.spine_count and s.joints_mm.shape[2] == 3
    # Hanging free, every joint is below its root (the hair points down).
    assert (s.joints_mm[:, -1, 2] < s.joints_mm[:, 0, 2]).all()


def test_pressed_5_mm_the_paper_pushes_up(round_brush):
    sim = bristle.Simulation(round_brush)
    length = round_brush.hair_length_mm
    # Upright, the tip first touches the paper with the ferrule at about the
    # hair's length; 5 mm lower the brush is pressed 5 mm.
    s = lowered(sim, 10, 10, length + 1, length - 5)
    assert s.in_contact and s.contact.any()
    assert s.force_n[2] > MIN_PRESS_FORCE_N, s.force_n
    assert s.t_s == pytest.approx(0.24)
    assert s.solved.all()
    # Nothing goes through the paper: the contact band is 0.1 mm
    # (RenderOptions.contact_band_mm), the solver's tolerance far below.
    assert np.nanmin(s.joints_mm[:, :, 2]) > -0.1


def test_step_without_time_advances_dt(round_brush):
    sim = bristle.Simulation(round_brush, dt_s=0.02)
    top = round_brush.hair_length_mm + 2
    assert sim.step([0, 0, top]).t_s == 0
    assert sim.step([0, 0, top - 0.25]).t_s == pytest.approx(0.02)
    assert sim.state.t_s == pytest.approx(0.02)


def test_a_simulation_keeps_its_brush_alive():
    # The Brush is a temporary: the simulation holds the brush's model itself.
    import gc
    sim = bristle.Simulation(bristle.Brush("round"))
    gc.collect()
    s = sim.step([0, 0, 30], t_s=0.2)
    assert s.t_s == pytest.approx(0.2) and s.joints_mm.shape[0] == 7
