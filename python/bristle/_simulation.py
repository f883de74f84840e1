"""bristle.Simulation: a brush stepped by the caller (bristle/simulation.h)."""
import numbers
import types

from . import Error, _brush, _bristle, _quaternions, _real_array


class State(types.SimpleNamespace):
    """The brush after a step. t_s; joints_mm (S, J, 3) float64, each spine's
    root then joints (NaN past a shorter spine's last joint); contact (S, J)
    bool, a joint on the paper (the root never); spine_force_n (S, 3) and
    force_n (3,), the paper's force on each spine and on the brush (N, +z up);
    contact_joints, joints on the paper; solved (S,) bool, False where a
    spine's solve failed and its shape was kept (docs/dynamics.md)."""

    @property
    def in_contact(self):
        return self.contact_joints > 0


def _time(where, t_s):
    if isinstance(t_s, bool) or not isinstance(t_s, numbers.Real):
        raise Error(f"{where}: t_s: must be a real number of seconds", 64)
    return float(t_s)


class Simulation:
    """The brush head simulated step by step as its handle moves (Baxter &
    Lin 2004, §3: each spine's joints solved for the least energy against
    the paper at z = 0), for control and learning.

    Simulation(brush, solver="ipopt" or "slsqp", solver_max_iterations=200,
    dt_s=0.01): dt_s is the time a step() without t_s advances. A step is
    solved well when no hair root moves more than about 0.25 mm; `bristle
    render` plans its steps so. The GIL is released during a step."""

    def __init__(self, brush, solver="ipopt", solver_max_iterations=200, dt_s=0.01):
        where = "Simulation"
        if solver not in ("ipopt", "slsqp"):
            raise Error(f"{where}: solver={solver!r}: must be one of ipopt, slsqp", 64)
        its = solver_max_iterations
        if isinstance(its, bool) or not isinstance(its, numbers.Integral):
            raise Error(f"{where}: solver_max_iterations: must be a whole number", 64)
        self.dt_s = _time(where, dt_s)
        if not self.dt_s > 0:
            raise Error(f"{where}: dt_s={dt_s!r}: must be > 0 s", 64)
        if not 1 <= its <= 100000:
            raise Error(f"{where}: solver_max_iterations {its}: must be in [1, 100000]", 64)
        self._s = _bristle.Simulation(_brush(where, brush), getattr(_bristle.Solver, solver),
                                      int(its))
        self._t_s = None

    def _pose(self, where, position_mm, quaternion_wxyz):
        xyz = _real_array(where, "position_mm", position_mm, (), 3)
        return xyz, _quaternions(where, quaternion_wxyz, 1)[0]

    def reset(self, position_mm, quaternion_wxyz=None, t_s=0.0):
        """The brush at rest at this ferrule pose (mm; w, x, y, z) at t_s."""
        xyz, q = self._pose("Simulation.reset", position_mm, quaternion_wxyz)
        state = State(**self._s.reset(xyz, q, _time("Simulation.reset", t_s)))
        self._t_s = state.t_s
        return state

    def step(self, position_mm, quaternion_wxyz=None, t_s=None):
        """One step to this ferrule pose at t_s (default: the last step's time
        + dt_s); the first step without reset() starts from rest there."""
        where = "Simulation.step"
        xyz, q = self._pose(where, position_mm, quaternion_wxyz)
        if t_s is None:
            t_s = 0.0 if self._t_s is None else self._t_s + self.dt_s
        state = State(**self._s.step(xyz, q, _time(where, t_s)))
        self._t_s = state.t_s
        return state

    @property
    def state(self):
        """The last step's State."""
        return State(**self._s.state())
