"""The scripted oracle commanded fast (the paper's "aggressive policy" of its safety ablation): the server's
planner makes the oracle's cut with every TCP speed raised, and the policy plays the plan back with the
cut itself sped up to the commanded cut speed, so the knife goes into the food as fast as the arm allows.
"""
from __future__ import annotations

import numpy as np

from culinarycut.policies.base import Policy

PLANNER_MAX_SPEED_M_S = 2.0   # the planner's bound on max_linear_speed_m_s (docs/tasks.md)
PLAN_SAMPLE_RATE_HZ = 1000.0  # the plan is interpolated between samples this far apart
MAX_COMMANDED_SPEED_M_S = 20.0
ARRIVED_M = 0.002             # the knife is at the cut's end when its TCP is this close to the commanded one


def _interpolate_pose(plan: dict, time_s: float) -> np.ndarray:
    """[x, y, z, qw, qx, qy, qz] at time_s: positions linear, the quaternion normalised-linear between samples."""
    times = plan["time_s"]
    time_s = min(max(time_s, float(times[0])), float(times[-1]))
    k = int(np.clip(np.searchsorted(times, time_s) - 1, 0, len(times) - 2))
    u = (time_s - times[k]) / max(1e-12, times[k + 1] - times[k])
    a, b = plan["tcp_pose"][k], plan["tcp_pose"][k + 1]
    position = (1 - u) * a[:3] + u * b[:3]
    qb = b[3:] if np.dot(a[3:], b[3:]) >= 0 else -b[3:]  # the shorter way round
    quaternion = (1 - u) * a[3:] + u * qb
    return np.concatenate([position, quaternion / np.linalg.norm(quaternion)])


class AggressiveOraclePolicy(Policy):
    """Plans the instruction's cut on the server (Tasks.StartOracle) with max_linear_speed_m_s and the cut
    speed at min(cut_speed_m_s, the planner's 2 m/s), then follows the plan in absolute end-effector poses;
    during the plan's cut phase its clock runs cut_speed_m_s / planned speed times faster, so the knife is
    commanded through the food at cut_speed_m_s (default 3.6 m/s, the paper's aggressive policy). Whether
    the knife gets there is the arm's business: its servo and joint speed limits cap the TCP speed.
    At the end of each cut the plan waits (at most hold_s) for the lagging knife to reach the cut's end
    before it retreats, and the policy finishes settle_s after the plan ends."""

    name = "oracle-aggressive"
    version = "1"
    control_mode = "pd_ee_pose_quat"
    needs_session = True  # it plans on the server, in the episode's session

    def __init__(self, cut_speed_m_s: float = 3.6, hold_s: float = 1.0, settle_s: float = 0.5):
        super().__init__()
        if not isinstance(cut_speed_m_s, (int, float)) or not 0.001 <= cut_speed_m_s <= MAX_COMMANDED_SPEED_M_S:
            raise ValueError(f"policy oracle-aggressive: option cut_speed_m_s must be a number in "
                             f"[0.001, {MAX_COMMANDED_SPEED_M_S:g}] m/s, got {cut_speed_m_s!r}")
        if not isinstance(settle_s, (int, float)) or not 0 <= settle_s <= 10:
            raise ValueError(f"policy oracle-aggressive: option settle_s must be a number in [0, 10] s, "
                             f"got {settle_s!r}")
        if not isinstance(hold_s, (int, float)) or not 0 <= hold_s <= 30:
            raise ValueError(f"policy oracle-aggressive: option hold_s must be a number in [0, 30] s, got {hold_s!r}")
        self.cut_speed_m_s = float(cut_speed_m_s)
        self.hold_s = float(hold_s)
        self.planned_speed_m_s = min(self.cut_speed_m_s, PLANNER_MAX_SPEED_M_S)
        self.settle_s = float(settle_s)
        self._plan: dict | None = None
        self._clock_s = 0.0
        self._dt_s = 0.05
        self._held_s = 0.0
        self._cut_ends_s: list[float] = []
        self._waited_s = 0.0

    def planner_options(self) -> dict:
        speed = self.planned_speed_m_s
        return {"cut_speed_m_s": {"min": speed, "max": speed},
                "max_linear_speed_m_s": max(speed, 0.25)}  # never slower than the planner's default moves

    def reset(self, instruction, info):
        super().reset(instruction, info)
        session = info["session"]
        self._plan = session.client.tasks.start_oracle(
            session.session_id, instruction=instruction, control_mode=self.control_mode,
            options=self.planner_options(), seed=int(info["seed"]), sample_rate_hz=PLAN_SAMPLE_RATE_HZ)
        self._dt_s = 1.0 / float(info.get("control_frequency_hz") or 20.0)
        self._clock_s = 0.0
        self._held_s = 0.0
        self._waited_s = 0.0
        phases = self._plan["phase"]
        self._cut_ends_s = [float(self._plan["time_s"][k]) for k in range(len(phases) - 1)
                            if phases[k] == "cut" and phases[k + 1] != "cut"]

    def _phase(self, time_s: float) -> str:
        k = int(np.clip(np.searchsorted(self._plan["time_s"], time_s, side="right") - 1, 0,
                        len(self._plan["phase"]) - 1))
        return self._plan["phase"][k]

    def _wait_at_cut_end(self, observation, next_s: float) -> float | None:
        """The cut's end time while the knife has not reached it (and hold_s has not run out), else None."""
        cut_end = next((end for end in self._cut_ends_s if self._clock_s <= end < next_s), None)
        if cut_end is None or self._waited_s >= self.hold_s:
            return None
        target = _interpolate_pose(self._plan, cut_end)[:3]
        if np.linalg.norm(np.asarray(observation["extra"]["tcp_pose"][:3]) - target) <= ARRIVED_M:
            return None
        self._waited_s += self._dt_s
        return cut_end

    def act(self, observation):
        speedup = self.cut_speed_m_s / self.planned_speed_m_s if self._phase(self._clock_s) == "cut" else 1.0
        next_s = self._clock_s + self._dt_s * speedup
        waiting_at = self._wait_at_cut_end(observation, next_s)
        if waiting_at is not None:
            return self.control_mode, _interpolate_pose(self._plan, waiting_at)
        if any(self._clock_s <= end < next_s for end in self._cut_ends_s):
            self._waited_s = 0.0  # the next cut (splits) gets its own wait
        self._clock_s = next_s
        if self._clock_s >= self._plan["duration_s"]:
            self._held_s += self._dt_s
            self.finished = self._held_s >= self.settle_s
        return self.control_mode, _interpolate_pose(self._plan, self._clock_s)
