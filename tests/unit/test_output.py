"""Tests of the output layer: variable registry, netCDF files, VTK snapshots."""

from __future__ import annotations

import errno
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sph.io import output
from sph.io.output import (
    OutputWriteError,
    VTKWriter,
    build_dataset,
    load_registry,
    read_dataset,
    write_netcdf_atomic,
)

# Units that xarray decodes as timedeltas; simulated time must never use them.
TIMEDELTA_UNITS = {
    "days",
    "hours",
    "minutes",
    "seconds",
    "milliseconds",
    "microseconds",
    "nanoseconds",
}


def _sample_dataset(n_time: int = 11) -> xr.Dataset:
    time = np.linspace(0.0, 2.5, n_time)
    rng = np.random.default_rng(1)
    series = {
        "sway": 0.1 * np.sin(time),
        "heave": -0.05 * time,
        "roll": 2.0 * np.cos(time),
        "flood_ratio": np.clip(time / 2.5, 0.0, 1.0),
        "n_particles": np.full(n_time, 12345, dtype=np.int64),
        "dt": np.full(n_time, 1.0e-3),
        "body_force_x": rng.normal(size=(2, n_time)),
    }
    probes = {
        "probe_elevation": (["WP1", "WP2"], rng.normal(size=(2, n_time))),
        "probe_pressure": (["P1"], 1.0e4 + rng.normal(size=(1, n_time))),
    }
    attrs = {
        "case_id": "A1",
        "opening": 0.5,
        "side": "back",
        "damaged": True,
        "unused": None,
        "wave": {"amplitude": 2.0, "omega": 1.0},
        "probe_x": [30.0, 60.0],
    }
    return build_dataset(
        time, series, probes=probes, attrs=attrs, config_yaml="case: A1\ndx: 0.4\n"
    )


# (a) -----------------------------------------------------------------------


def test_registry_entries_have_units_and_long_name():
    registry = load_registry()
    assert registry, "registry is empty"
    for name, entry in registry.items():
        assert isinstance(entry.get("long_name"), str) and entry["long_name"], name
        if entry.get("dtype") == "str":
            # string labels (probe names) carry no units
            assert "units" not in entry, name
        else:
            assert isinstance(entry.get("units"), str) and entry["units"], name
            assert entry["units"] not in TIMEDELTA_UNITS, name
        if "dim" in entry:
            assert entry["dim"] in registry, f"{name}: dim {entry['dim']} not registered"


def test_registry_covers_data_contract_and_is_a_copy():
    registry = load_registry()
    for name in (
        "time",
        "sway",
        "heave",
        "roll",
        "flood_volume",
        "flood_ratio",
        "probe_elevation",
        "probe",
        "body_force_x",
        "body_force_z",
        "body_moment",
        "n_particles",
        "dt",
        "volume_error",
    ):
        assert name in registry
    assert registry["time"]["units"] == "s"
    assert registry["roll"]["units"] == "degree"
    registry["time"]["units"] = "changed"
    assert load_registry()["time"]["units"] == "s"


# (b) -----------------------------------------------------------------------


def test_roundtrip_keeps_values_units_and_probe_coordinate(tmp_path):
    ds = _sample_dataset()
    path = write_netcdf_atomic(ds, tmp_path / "sub" / "case.nc")
    assert path.exists()

    with xr.open_dataset(path) as back:
        back.load()
    assert back["time"].dtype == np.float64  # not decoded to timedelta64
    assert back["time"].attrs["units"] == "s"
    assert back["time"].attrs["standard_name"] == "time"
    np.testing.assert_array_equal(back["time"].values, ds["time"].values)
    for name in ds.data_vars:
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].attrs["units"] == ds[name].attrs["units"]
        assert back[name].attrs["long_name"] == ds[name].attrs["long_name"]
    assert list(back["probe"].values) == ["WP1", "WP2"]
    assert list(back["pressure_probe"].values) == ["P1"]
    assert back["probe_elevation"].dims == ("probe", "time")
    assert back["probe_pressure"].dims == ("pressure_probe", "time")
    assert back["body_force_x"].dims == ("body", "time")
    assert list(back["body"].values) == [0, 1]
    assert back["roll"].attrs["units"] == "degree"

    # global attributes
    assert back.attrs["Conventions"] == "CF-1.10"
    assert back.attrs["source"].startswith("sph-flood ")
    assert "created" in back.attrs["history"]
    assert back.attrs["config"] == "case: A1\ndx: 0.4\n"
    assert back.attrs["case_id"] == "A1"
    assert back.attrs["opening"] == 0.5
    assert back.attrs["damaged"] == 1
    assert back.attrs["wave_amplitude"] == 2.0
    assert isinstance(back.attrs["probe_x"], str)
    assert "unused" not in back.attrs


def test_encoding_compression_and_no_fill_on_coordinates(tmp_path):
    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        assert nc["time"].dtype == np.float64
        for coord in ("time", "probe", "body"):
            assert "_FillValue" not in nc[coord].ncattrs(), coord
        assert nc["roll"].filters()["zlib"] is True
        assert nc["roll"].filters()["complevel"] == 4


def test_read_dataset_returns_closed_in_memory_copy(tmp_path):
    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    ds = read_dataset(path)
    os.remove(path)  # the file is no longer needed once read
    assert ds["time"].dtype == np.float64
    assert float(ds["sway"].sum()) == pytest.approx(float(_sample_dataset()["sway"].sum()))


def test_source_falls_back_to_unknown_without_version(monkeypatch):
    monkeypatch.setattr(output, "_package_version", lambda: "unknown")
    ds = build_dataset([0.0, 1.0], {"heave": [0.0, 0.1]})
    assert ds.attrs["source"] == "sph-flood unknown"


# (c) -----------------------------------------------------------------------


def test_unregistered_series_name_raises_key_error():
    with pytest.raises(KeyError, match="not_a_variable"):
        build_dataset([0.0, 1.0], {"heave": [0.0, 0.1], "not_a_variable": [1.0, 2.0]})


def test_unregistered_probe_variable_raises_key_error():
    with pytest.raises(KeyError, match="mystery_probe"):
        build_dataset([0.0, 1.0], {}, probes={"mystery_probe": (["A"], [[1.0, 2.0]])})


def test_shape_mismatch_and_inconsistent_probe_names_are_refused():
    with pytest.raises(ValueError, match="heave"):
        build_dataset([0.0, 1.0, 2.0], {"heave": [0.0, 0.1]})
    with pytest.raises(ValueError, match="surface_height"):
        build_dataset(
            [0.0, 1.0],
            {},
            probes={
                "probe_elevation": (["WP1", "WP2"], np.zeros((2, 2))),
                "surface_height": (["WP2", "WP1"], np.zeros((2, 2))),
            },
        )
    with pytest.raises(ValueError, match="reserved"):
        build_dataset([0.0], {"heave": [0.0]}, attrs={"Conventions": "x"})


# (d) -----------------------------------------------------------------------


def _leftovers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if ".tmp-" in p.name)


def test_failed_write_keeps_previous_file_and_removes_temp(tmp_path, monkeypatch):
    path = tmp_path / "case.nc"
    write_netcdf_atomic(_sample_dataset(), path)
    before = path.read_bytes()

    def half_write_then_fail(self, target, *args, **kwargs):
        Path(target).write_bytes(b"CDF partial")
        raise RuntimeError("simulated failure midway")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", half_write_then_fail)
    with pytest.raises(RuntimeError, match="simulated failure"):
        write_netcdf_atomic(_sample_dataset(5), path)
    assert path.read_bytes() == before
    assert _leftovers(tmp_path) == []


def test_disk_full_is_reported_as_oserror_naming_path(tmp_path, monkeypatch):
    path = tmp_path / "case.nc"

    def no_space(self, target, *args, **kwargs):
        Path(target).write_bytes(b"CDF")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", no_space)
    with pytest.raises(OutputWriteError, match="case.nc") as info:
        write_netcdf_atomic(_sample_dataset(), path)
    assert isinstance(info.value, OSError)
    assert info.value.errno == errno.ENOSPC
    assert "disk full" in str(info.value)
    assert not path.exists()
    assert _leftovers(tmp_path) == []


def test_netcdf_library_error_is_reported_as_oserror(tmp_path, monkeypatch):
    def hdf_error(self, target, *args, **kwargs):
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", hdf_error)
    with pytest.raises(OutputWriteError, match="case.nc"):
        write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")


# (e) -----------------------------------------------------------------------


def test_unwritable_directory_error_names_path(tmp_path, monkeypatch):
    """Simulated so that it also holds when the suite runs as root."""
    path = tmp_path / "locked" / "case.nc"
    real_mkdir = Path.mkdir

    def denied_mkdir(self, *args, **kwargs):
        if self == path.parent:
            raise PermissionError(errno.EACCES, "Permission denied", str(self))
        return real_mkdir(self, *args, **kwargs)

    monkeypatch.setattr(Path, "mkdir", denied_mkdir)
    with pytest.raises(OutputWriteError, match="locked") as info:
        write_netcdf_atomic(_sample_dataset(), path)
    assert str(path) in str(info.value)
    assert info.value.errno == errno.EACCES


def test_parent_that_is_a_file_error_names_path(tmp_path):
    """A real OS failure that does not depend on the user's privileges."""
    blocker = tmp_path / "results"
    blocker.write_text("not a directory")
    path = blocker / "case.nc"
    with pytest.raises(OutputWriteError) as info:
        write_netcdf_atomic(_sample_dataset(), path)
    assert str(path) in str(info.value)
    assert "cannot create directory" in str(info.value)
    assert blocker.read_text() == "not a directory"


@pytest.mark.skipif(
    hasattr(os, "geteuid") and os.geteuid() == 0, reason="root ignores directory permissions"
)
def test_read_only_directory_error_names_path(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        with pytest.raises(OutputWriteError) as info:
            write_netcdf_atomic(_sample_dataset(), locked / "case.nc")
        assert str(locked / "case.nc") in str(info.value)
    finally:
        locked.chmod(0o700)


# (f) -----------------------------------------------------------------------


def test_truncated_file_raises_value_error_naming_path(tmp_path):
    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    size = path.stat().st_size
    with open(path, "r+b") as fh:
        fh.truncate(size // 2)
    with pytest.raises(ValueError, match="not a readable netCDF file") as info:
        read_dataset(path)
    assert str(path) in str(info.value)


def test_missing_file_raises_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_dataset(tmp_path / "absent.nc")


# (g) -----------------------------------------------------------------------


def _pvd_entries(path: Path) -> list[tuple[float, str]]:
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.attrib["type"] == "Collection"
    return [(float(d.attrib["timestep"]), d.attrib["file"]) for d in root.iter("DataSet")]


def test_vtk_writer_snapshots_and_collection(tmp_path):
    n_snap, n = 4, 50
    times = [0.0, 0.125, 0.25, 1.0 / 3.0]
    rng = np.random.default_rng(0)
    writer = VTKWriter(tmp_path / "vtk", "particles")
    for k, t in enumerate(times):
        x = rng.random(n)
        z = rng.random(n).astype(np.float32)  # converted to float64 inside
        fields = {
            "pressure": rng.random(n),
            "compartment": np.arange(n, dtype=np.int64) % 3,  # written as int32
            "velocity": rng.random((n, 2))[::1],  # 2-D vector (vx, vz)
            "density": rng.random(2 * n)[::2],  # non-contiguous view
        }
        written = writer.write(t, x, z, fields)
        assert written.name == f"particles_{k:06d}.vtu"
        # collection usable after every snapshot
        assert len(_pvd_entries(writer.pvd_path)) == k + 1
    writer.close()

    vtus = sorted((tmp_path / "vtk").glob("*.vtu"))
    assert [p.name for p in vtus] == [f"particles_{k:06d}.vtu" for k in range(n_snap)]
    entries = _pvd_entries(tmp_path / "vtk" / "particles.pvd")
    assert [f for _, f in entries] == [p.name for p in vtus]
    assert [t for t, _ in entries] == times  # exact, written with repr()

    content = vtus[0].read_bytes()
    assert b"UnstructuredGrid" in content
    for name in (b"pressure", b"compartment", b"velocity", b"density"):
        assert name in content
    assert b'NumberOfPoints="50"' in content

    with pytest.raises(RuntimeError):
        writer.write(2.0, np.zeros(3), np.zeros(3), {})


def test_vtk_writer_resume_keeps_earlier_entries(tmp_path):
    x = z = np.linspace(0.0, 1.0, 5)
    with VTKWriter(tmp_path, "p") as writer:
        for t in (0.0, 1.0, 2.0):
            writer.write(t, x, z, {})
    with VTKWriter(tmp_path, "p", resume_after=1.0) as writer:
        assert writer.n_written == 2
        assert writer.write(1.5, x, z, {"rho": np.ones(5)}).name == "p_000002.vtu"
    assert _pvd_entries(tmp_path / "p.pvd") == [
        (0.0, "p_000000.vtu"),
        (1.0, "p_000001.vtu"),
        (1.5, "p_000002.vtu"),
    ]


def test_vtk_writer_rejects_bad_field_shape(tmp_path):
    writer = VTKWriter(tmp_path, "p")
    with pytest.raises(ValueError, match="pressure"):
        writer.write(0.0, np.zeros(4), np.zeros(4), {"pressure": np.zeros(3)})


# (h) content checksum ----------------------------------------------------------


def test_written_file_carries_a_checksum_that_read_dataset_checks(tmp_path):
    import netCDF4

    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    with netCDF4.Dataset(path) as nc:
        stamp = nc.getncattr(output.CHECKSUM_ATTR)
    assert len(stamp) == 64
    ds = read_dataset(path)
    assert output.CHECKSUM_ATTR not in ds.attrs  # a property of the file, not of the data
    assert output.content_digest(ds) == stamp
    # a dataset read back and written again gets a fresh, valid stamp
    ds.attrs["title"] = "changed"
    read_dataset(write_netcdf_atomic(ds, tmp_path / "again.nc"))


@pytest.mark.parametrize("keep", [0.1, 0.5, 0.9, 0.99, -1])
def test_truncated_file_is_refused_at_any_length(tmp_path, keep):
    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * keep)] if keep > 0 else data[:-1])
    with pytest.raises(ValueError, match="not a readable netCDF file") as info:
        read_dataset(path)
    assert str(path) in str(info.value)


def test_changed_bytes_are_refused_or_harmless(tmp_path):
    """Flip one byte at a time at 120 places across the file: every flip is refused or
    leaves the content unchanged, never read as valid but different data."""
    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    data = path.read_bytes()
    good = read_dataset(path)
    refused = harmless = 0
    for pos in range(3, len(data), len(data) // 120):
        path.write_bytes(data[:pos] + bytes([data[pos] ^ 0x24]) + data[pos + 1:])
        try:
            ds = read_dataset(path)
        except ValueError as exc:
            assert str(path) in str(exc)
            refused += 1
            continue
        assert ds.identical(good), pos
        harmless += 1
    assert refused > 0 and harmless > 0


def test_corrupt_value_names_the_checksum(tmp_path):
    import netCDF4

    path = write_netcdf_atomic(_sample_dataset(), tmp_path / "case.nc")
    with netCDF4.Dataset(path, mode="a") as nc:  # a change behind the writer's back
        nc["heave"][3] = 99.0
    with pytest.raises(ValueError, match="does not match the checksum") as info:
        read_dataset(path)
    assert str(path) in str(info.value)


def test_file_without_checksum_is_read_unchecked(tmp_path):
    path = tmp_path / "plain.nc"
    _sample_dataset().to_netcdf(path)
    assert read_dataset(path).sizes["time"] == 11
