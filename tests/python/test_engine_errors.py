"""An engine failure inside Step reaches the client as a typed status, and the session is marked broken
(never left half-stepped, never UNKNOWN) until Reset or RestoreSnapshot."""
from __future__ import annotations

import struct

import numpy as np
import pytest

from culinarycut.errors import FailedPrecondition, Internal

SCENE = {"quality": "draft",
         "effects": {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True},
         "objects": [{"food": "cucumber"}]}

# Snapshot layout (sim/world/state_fields.h): magic (8), model fingerprint (8), has-food flag (1),
# frame_id (8), sim_time_s (8), seed (8), episode_steps (4), then three joint vectors of
# (uint32 length + 7 doubles), then the food's particle arrays, each a count (uint64) and float32s:
# position x, y, z first.
FOOD = 8 + 8 + 1 + 8 + 8 + 8 + 4 + 3 * (4 + 7 * 8)


def runaway_snapshot(snapshot: bytes) -> bytes:
    """A well-formed snapshot whose first particle sits 1e30 m up: finite, but no grid can hold it.
    Its bounding box then reaches the knife, so the food wakes at the next Step."""
    (count,) = struct.unpack_from("<Q", snapshot, FOOD)
    first_z = FOOD + 2 * (8 + 4 * count) + 8
    return snapshot[:first_z] + struct.pack("<f", 1e30) + snapshot[first_z + 4:]


def test_a_failing_step_breaks_the_session_until_reset(client):
    session = client.create_session(SCENE).session_id
    client.reset(session, seed=0)
    good = client.save_snapshot(session)
    client.restore_snapshot(session, runaway_snapshot(good))

    with pytest.raises(Internal) as failure:
        client.step(session, "pd_joint_delta_pos", np.zeros(7))
    assert "broken" in failure.value.details and "Reset" in failure.value.details
    assert "far from the origin" in failure.value.details  # the engine's own reason travels with it

    # The half-stepped state is never served: every call that needs it says why and how to recover.
    with pytest.raises(FailedPrecondition, match="broken"):
        client.step(session, "pd_joint_delta_pos", np.zeros(7))
    with pytest.raises(FailedPrecondition, match="broken"):
        client.observe(session)
    with pytest.raises(FailedPrecondition, match="broken"):
        client.save_snapshot(session)

    # Restoring a good snapshot recovers, and so does Reset.
    client.restore_snapshot(session, good)
    assert client.step(session, "pd_joint_delta_pos", np.zeros(7)).stamp.frame_id == 1
    client.restore_snapshot(session, runaway_snapshot(good))
    with pytest.raises(Internal):
        client.step(session, "pd_joint_delta_pos", np.zeros(7))
    client.reset(session, seed=0)
    assert client.step(session, "pd_joint_delta_pos", np.zeros(7)).stamp.frame_id == 1
    client.close_session(session)
