"""Snapshots a client holds cannot hurt the server: a blob this server did not write (or that was
changed) is refused naming the reason, and even a correctly authenticated blob is range-checked field by
field. A refused restore leaves the session exactly as it was."""
from __future__ import annotations

import hashlib
import hmac
import struct

import numpy as np
import pytest

from culinarycut import Client
from culinarycut.errors import InvalidArgument
from culinarycut.launch import ServerProcess, server_binary

SCENE = {"quality": "draft",
         "effects": {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True},
         "objects": [{"food": "cucumber"}]}

# Sealed snapshot: "CCSEAL01", HMAC-SHA256 tag (32 bytes) of the engine's bytes, the engine's bytes.
# Engine bytes (sim/world/state_fields.h): magic (8), model fingerprint (8), has-food flag (1),
# frame_id (8), sim_time_s (8), seed (8), episode_steps (4), the safety limiter's episode totals (3
# uint64 interventions, 4 doubles, 1 bool), three joint vectors of (uint32 length + 7 doubles), then the
# food's particle arrays, each a count (uint64) and its values: position x, y, z
# (float32), velocity x, y, z, rest position x, y, z, F (9), C (9), mass, volume, plastic strain, Maxwell branch
# stress (6), damage (float32), piece (int32), blade side (int8), cut sides (uint32), material (uint16), object (uint16).
SEAL_HEADER = 8 + 32
SAFETY = 3 * 8 + 4 * 8 + 1
FOOD = 8 + 8 + 1 + 8 + 8 + 8 + 4 + SAFETY + 3 * (4 + 7 * 8)


def engine_bytes(sealed: bytes) -> bytes:
    return sealed[SEAL_HEADER:]


def reseal(engine: bytes, key: bytes) -> bytes:
    return b"CCSEAL01" + hmac.new(key, engine, hashlib.sha256).digest() + engine


def array_offset(engine: bytes, index: int, item_sizes: list[int]) -> int:
    """Offset of the first value of the food's `index`-th particle array."""
    (count,) = struct.unpack_from("<Q", engine, FOOD)
    offset = FOOD
    for size in item_sizes[:index]:
        offset += 8 + size * count
    return offset + 8


# Item sizes of the particle arrays in order: 3 positions, 3 velocities, 3 rest positions, 9 F, 9 C, mass, volume,
# plastic strain, 6 Maxwell stresses, damage, piece, blade side, cut sides, material, object.
ITEM_SIZES = [4] * 3 + [4] * 3 + [4] * 3 + [4] * 9 + [4] * 9 + [4, 4, 4] + [4] * 6 + [4, 4, 1, 4, 2, 2]
CUT_SIDES, MATERIAL, OBJECT, POSITION_Z, VELOCITY_X, REST_Z, MASS, MAXWELL_XY = 39, 40, 41, 2, 3, 8, 27, 33


def patched(engine: bytes, array: int, fmt: str, value) -> bytes:
    offset = array_offset(engine, array, ITEM_SIZES)
    packed = struct.pack(fmt, value)
    return engine[:offset] + packed + engine[offset + len(packed):]


@pytest.fixture
def keyed_server(tmp_path):
    key = bytes(range(32))
    key_file = tmp_path / "snapshot.key"
    key_file.write_bytes(key)
    with ServerProcess(server_binary(), max_sessions=4, extra_args=["--snapshot-key-file", str(key_file)]) as server:
        yield server, key, key_file


def test_a_changed_snapshot_is_refused_and_changes_nothing(client):
    session = client.create_session(SCENE).session_id
    client.reset(session, seed=0)
    good = client.save_snapshot(session)
    client.step(session, "pd_joint_delta_pos", np.zeros(7))
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x01
    with pytest.raises(InvalidArgument, match=r"snapshot .*authentication"):
        client.restore_snapshot(session, bytes(flipped))
    with pytest.raises(InvalidArgument, match=r"snapshot .*bad header"):
        client.restore_snapshot(session, b"garbage")
    assert client.observe(session).stamp.frame_id == 1  # untouched
    client.restore_snapshot(session, good)
    assert client.observe(session).stamp.frame_id == 0
    client.close_session(session)


def test_snapshots_move_between_servers_only_with_a_shared_key(client, keyed_server, tmp_path):
    server, _, key_file = keyed_server
    with Client(server.address) as keyed:
        session = keyed.create_session(SCENE).session_id
        keyed.reset(session, seed=0)
        sealed = keyed.save_snapshot(session)
        other = client.create_session(SCENE).session_id  # the shared test server: its own random key
        with pytest.raises(InvalidArgument, match="authentication"):
            client.restore_snapshot(other, sealed)
        client.close_session(other)
    with ServerProcess(server_binary(), max_sessions=1, extra_args=["--snapshot-key-file", str(key_file)]) as twin, \
            Client(twin.address) as twin_client:
        session = twin_client.create_session(SCENE).session_id
        twin_client.restore_snapshot(session, sealed)
        assert twin_client.observe(session).stamp.frame_id == 0


@pytest.mark.parametrize("array, fmt, value, field", [
    (MATERIAL, "<H", 65535, "food.material"),
    (OBJECT, "<H", 60000, "food.object"),
    (POSITION_Z, "<f", 1e30, "food.position"),
    (POSITION_Z, "<f", float("nan"), "food.position"),
    (MASS, "<f", -1.0, "food.mass"),
    (VELOCITY_X, "<f", float("nan"), "food.velocity"),
    (VELOCITY_X, "<f", 1e6, "food.velocity"),
    (CUT_SIDES, "<I", 0b10, "food.cut_sides"),
    (REST_Z, "<f", float("inf"), "food.rest_position"),
    (MAXWELL_XY, "<f", float("nan"), "food.maxwell_stress"),
])
def test_authentic_but_impossible_snapshots_are_refused_naming_the_field(keyed_server, array, fmt, value, field):
    server, key, _ = keyed_server
    with Client(server.address) as client:
        session = client.create_session(SCENE).session_id
        client.reset(session, seed=0)
        engine = engine_bytes(client.save_snapshot(session))
        with pytest.raises(InvalidArgument, match=field):
            client.restore_snapshot(session, reseal(patched(engine, array, fmt, value), key))
        # The session is as it was and steps on.
        assert client.step(session, "pd_joint_delta_pos", np.zeros(7)).stamp.frame_id == 1
        client.close_session(session)


def test_impossible_counters_are_refused(keyed_server):
    server, key, _ = keyed_server
    with Client(server.address) as client:
        session = client.create_session({}).session_id
        client.reset(session, seed=0)
        engine = engine_bytes(client.save_snapshot(session))
        frame_id_offset = 8 + 8 + 1
        wrapped = engine[:frame_id_offset] + struct.pack("<Q", 2**64 - 1) + engine[frame_id_offset + 8:]
        with pytest.raises(InvalidArgument, match="episode_steps"):
            client.restore_snapshot(session, reseal(wrapped, key))
        sim_time_offset = frame_id_offset + 8
        far_future = engine[:sim_time_offset] + struct.pack("<d", 1e300) + engine[sim_time_offset + 8:]
        with pytest.raises(InvalidArgument, match="sim_time_s"):
            client.restore_snapshot(session, reseal(far_future, key))
