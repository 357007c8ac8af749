"""Output layer: CF-annotated netCDF time series and VTK particle snapshots.

Every name written to a netCDF file must be declared in ``variables.yaml``,
the single registry of output variables, their units and long names. The
functions here attach those attributes, add the CF global attributes and write
files atomically, so that an interrupted or failed write never leaves a
half-written result where a complete one is expected.

Particle snapshots for ParaView are written by :class:`VTKWriter` as one
``.vtu`` point cloud per output time plus a ``.pvd`` collection that indexes
them by simulated time.
"""

from __future__ import annotations

import copy
import datetime as _dt
import errno
import functools
import numbers
import os
import sys
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import yaml

from sph import __version__
from sph.io.atomic import OutputWriteError, write_atomic

__all__ = [
    "OutputWriteError",
    "VTKWriter",
    "build_dataset",
    "content_digest",
    "load_registry",
    "read_dataset",
    "write_netcdf_atomic",
]

#: Registry keys written to the netCDF file as variable attributes.
_ATTRIBUTE_KEYS = ("units", "long_name", "standard_name")

#: Global attributes set by :func:`build_dataset` that ``attrs`` may not override.
_RESERVED_GLOBAL_ATTRS = frozenset({"Conventions", "source", "history", "config",
                                    "content_sha256"})

#: Global attribute holding the SHA-256 of a written file's content (see
#: :func:`content_digest`); :func:`read_dataset` checks it.
CHECKSUM_ATTR = "content_sha256"

_DEFAULT_TITLE = "sph-flood simulation output"

#: Compression applied to every numeric data variable.
_COMPRESSION = {"zlib": True, "complevel": 4}


# ---------------------------------------------------------------------------
# registry
# ---------------------------------------------------------------------------


@functools.lru_cache(maxsize=1)
def _registry() -> dict[str, dict[str, Any]]:
    package = __package__ or "sph.io"
    text = resources.files(package).joinpath("variables.yaml").read_text(encoding="utf-8")
    registry = yaml.safe_load(text)
    if not isinstance(registry, dict):
        raise ValueError("variables.yaml must be a mapping of variable names to entries")
    return registry


def load_registry() -> dict[str, dict[str, Any]]:
    """Return the output-variable registry read from ``variables.yaml``.

    The file is parsed once per process; each call returns a fresh deep copy,
    so callers may modify the result without affecting later calls.

    Returns
    -------
    dict
        Mapping ``name -> entry``. Every entry has ``long_name``; every entry
        except string-label coordinates (``dtype: str``) has ``units``;
        ``standard_name`` appears where a CF standard name fits. ``dim`` names
        the leading dimension of variables stored as ``(dim, time)``.
    """
    return copy.deepcopy(_registry())


def _entry(name: str) -> dict[str, Any]:
    registry = _registry()
    if name not in registry:
        raise KeyError(
            f"output variable {name!r} is not declared in sph/variables.yaml; "
            "add it there (units, long_name) before writing it"
        )
    return registry[name]


def cf_attrs(name: str) -> dict[str, str]:
    entry = _entry(name)
    return {key: str(entry[key]) for key in _ATTRIBUTE_KEYS if key in entry}


def _is_label_coord(name: str) -> bool:
    return _entry(name).get("dtype") == "str"


# ---------------------------------------------------------------------------
# dataset construction
# ---------------------------------------------------------------------------


def _package_version() -> str:
    return __version__


def _attr_value(value: Any) -> Any:
    """Convert one attribute value to something netCDF can store, or None to skip."""
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, (str, numbers.Integral, numbers.Real)):
        return value
    return str(value)


def _flatten_attrs(attrs: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Flatten nested mappings into ``outer_inner`` keys with netCDF-safe values."""
    flat: dict[str, Any] = {}
    for key, value in attrs.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            items = _flatten_attrs(value, prefix=f"{name}_")
        else:
            converted = _attr_value(value)
            items = {} if converted is None else {name: converted}
        for item_name, item_value in items.items():
            if item_name in flat:
                raise ValueError(f"attribute {item_name!r} appears twice after flattening attrs")
            flat[item_name] = item_value
    return flat


def _as_numeric(name: str, values: Any) -> np.ndarray:
    array = np.asarray(values)
    if array.dtype == bool:
        array = array.astype(np.int8)
    if not np.issubdtype(array.dtype, np.number):
        raise TypeError(f"output variable {name!r} must be numeric, got dtype {array.dtype}")
    return array


def build_dataset(
    time: Sequence[float] | np.ndarray,
    series: Mapping[str, Any],
    *,
    probes: Mapping[str, tuple[Sequence[str], Any]] | None = None,
    attrs: Mapping[str, Any] | None = None,
    config_yaml: str | None = None,
) -> xr.Dataset:
    """Assemble a CF-annotated dataset of time series from one simulation.

    Parameters
    ----------
    time : array_like, shape (n_time,)
        Output times in s.
    series : mapping of str to array_like
        Variable name -> values over time, shape ``(n_time,)``. Variables
        whose registry entry declares a ``dim`` with integer ids (``body_*``,
        ``dim: body``) may also be given as ``(n_body, n_time)``; the ``body``
        coordinate is then ``0 .. n_body - 1``.
    probes : mapping, optional
        Variable name -> ``(probe_names, values)`` with ``values`` of shape
        ``(n_probe, n_time)``, e.g.
        ``{"probe_elevation": (["WP1", "WP2"], eta), "probe_pressure": (["P1"], p)}``.
        The probe dimension is the variable's registry ``dim`` (``probe`` for
        wave probes, ``pressure_probe`` for pressure probes); variables sharing
        a dimension must use the same probe names in the same order.
    attrs : mapping, optional
        Case parameters and other global attributes. Nested mappings are
        flattened to ``outer_inner`` names, booleans stored as 0/1, ``None``
        skipped and any other non-scalar converted to ``str``. ``title`` may be
        given here; ``Conventions``, ``source``, ``history`` and ``config`` are
        reserved.
    config_yaml : str, optional
        Full resolved configuration as YAML text, stored as the global
        attribute ``config``.

    Returns
    -------
    xarray.Dataset
        Dataset with dimension ``time`` and every variable annotated from the
        registry.

    Raises
    ------
    KeyError
        If a variable name is not declared in the registry.
    ValueError
        If shapes do not match ``time``, probe names are inconsistent or an
        attribute name is reserved.
    """
    time_values = np.asarray(time, dtype=np.float64)
    if time_values.ndim != 1:
        raise ValueError(f"time must be 1-D, got shape {time_values.shape}")
    n_time = time_values.size

    coords: dict[str, xr.Variable] = {"time": xr.Variable("time", time_values, cf_attrs("time"))}
    data_vars: dict[str, xr.Variable] = {}

    for name, values in series.items():
        entry = _entry(name)
        array = _as_numeric(name, values)
        if array.ndim == 1:
            dims: tuple[str, ...] = ("time",)
        elif array.ndim == 2 and "dim" in entry:
            dim = entry["dim"]
            if _is_label_coord(dim):
                raise ValueError(
                    f"{name!r} is indexed by named {dim!r} entries; pass it through probes="
                )
            ids = np.arange(array.shape[0], dtype=np.int32)
            if dim in coords and not np.array_equal(coords[dim].values, ids):
                raise ValueError(
                    f"{name!r} has {ids.size} entries along {dim!r}, "
                    f"other variables have {coords[dim].size}"
                )
            coords[dim] = xr.Variable(dim, ids, cf_attrs(dim))
            dims = (dim, "time")
        else:
            raise ValueError(f"{name!r} must be 1-D over time, got shape {array.shape}")
        if array.shape[-1] != n_time:
            raise ValueError(f"{name!r} has {array.shape[-1]} values along time, expected {n_time}")
        data_vars[name] = xr.Variable(dims, array, cf_attrs(name))

    for name, (names, values) in (probes or {}).items():
        if name in data_vars:
            raise ValueError(f"{name!r} is given both in series and in probes")
        entry = _entry(name)
        dim = str(entry.get("dim", "probe"))
        _entry(dim)  # the probe dimension must be registered too
        labels = np.asarray([str(label) for label in names], dtype=object)
        array = _as_numeric(name, values)
        if array.ndim == 1 and labels.size == 1:
            array = array[np.newaxis, :]
        if array.shape != (labels.size, n_time):
            raise ValueError(
                f"{name!r} must have shape (n_probe, n_time) = ({labels.size}, {n_time}), "
                f"got {array.shape}"
            )
        if len(set(labels)) != labels.size:
            raise ValueError(f"{name!r} has duplicate probe names: {list(labels)}")
        if dim in coords:
            if list(coords[dim].values) != list(labels):
                raise ValueError(
                    f"{name!r} uses {dim!r} names {list(labels)}, but another variable "
                    f"uses {list(coords[dim].values)}; give it its own dim in variables.yaml"
                )
        else:
            coords[dim] = xr.Variable(dim, labels, cf_attrs(dim))
        data_vars[name] = xr.Variable((dim, "time"), array, cf_attrs(name))

    global_attrs: dict[str, Any] = {"Conventions": "CF-1.10", "title": _DEFAULT_TITLE}
    source = f"sph-flood {_package_version()}"
    global_attrs["source"] = source
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    global_attrs["history"] = f"{stamp}: created by {source}"
    flat = _flatten_attrs(attrs or {})
    clash = sorted(_RESERVED_GLOBAL_ATTRS & flat.keys())
    if clash:
        raise ValueError(f"attrs may not set reserved global attributes {clash}")
    global_attrs.update(flat)
    if config_yaml is not None:
        global_attrs["config"] = str(config_yaml)

    return xr.Dataset(data_vars=data_vars, coords=coords, attrs=global_attrs)


# ---------------------------------------------------------------------------
# netCDF writing and reading
# ---------------------------------------------------------------------------


def _netcdf_encoding(ds: xr.Dataset) -> dict[str, dict[str, Any]]:
    encoding: dict[str, dict[str, Any]] = {}
    for name, var in ds.variables.items():
        if name in ds.coords:
            enc: dict[str, Any] = {"_FillValue": None}
        elif np.issubdtype(var.dtype, np.number):
            enc = dict(_COMPRESSION)
        else:
            enc = {}
        if name == "time":
            enc["dtype"] = "float64"
        encoding[str(name)] = enc
    return encoding


def write_netcdf_atomic(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """Write a dataset to netCDF-4 so that ``path`` is either old or complete.

    The data go to a hidden temporary file ``.{name}.tmp-{pid}`` in the target
    directory, which is read back, stamped with the SHA-256 of its content
    (global attribute ``content_sha256``, checked by :func:`read_dataset`),
    flushed to disk and then renamed onto ``path`` with :func:`os.replace`
    (atomic on POSIX). If anything fails, the temporary file is removed and a
    file already at ``path`` is left untouched.

    ``time`` is stored as float64; coordinates get no ``_FillValue``; numeric
    data variables are zlib-compressed at level 4.

    Parameters
    ----------
    ds : xarray.Dataset
        Dataset to write, typically from :func:`build_dataset`.
    path : str or os.PathLike
        Destination file. Missing parent directories are created.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    OutputWriteError
        (a subclass of :class:`OSError`) if the directory cannot be created or
        written, the disk is full, or the netCDF library fails while writing.
        The message names ``path``.
    """
    def write(tmp: Path) -> None:
        ds.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4",
                     encoding=_netcdf_encoding(ds))
        _add_checksum(tmp)

    # RuntimeError "NetCDF: ...": errors reported by the netCDF/HDF5 library itself (HDF5
    # reports a full disk so)
    return write_atomic(path, write, "netCDF file", lambda exc: isinstance(exc, RuntimeError)
                        and str(exc).startswith("NetCDF:"))


def read_dataset(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a netCDF file fully into memory and close it.

    Times in ``s`` are returned as plain floats (no timedelta decoding).

    Parameters
    ----------
    path : str or os.PathLike
        netCDF file to read.

    Returns
    -------
    xarray.Dataset
        In-memory dataset; the file is closed and may be replaced or deleted.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file exists but cannot be read as netCDF (truncated, corrupt,
        not netCDF), or its content does not match the ``content_sha256``
        checksum stamped on it by :func:`write_netcdf_atomic`. The message
        names ``path``. (The checksum attribute is not part of the returned
        dataset; files without one are read unchecked.)
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(errno.ENOENT, "no such netCDF file", str(path))
    ds = _load(path)
    stamp = ds.attrs.pop(CHECKSUM_ATTR, None)
    if stamp is not None and str(stamp) != content_digest(ds):
        raise ValueError(
            f"{str(path)!r} is corrupt: its content does not match the checksum "
            f"({CHECKSUM_ATTR}) written with it"
        )
    return ds


def _load(path: Path) -> xr.Dataset:
    try:
        with xr.open_dataset(path, engine="netcdf4", decode_timedelta=False) as ds:
            return ds.load()
    except (OSError, RuntimeError, ValueError, KeyError, IndexError) as exc:
        raise ValueError(
            f"{str(path)!r} is not a readable netCDF file (truncated or corrupt?): {exc}"
        ) from exc


def _canonical(value: Any) -> bytes:
    if isinstance(value, str):
        return b"s" + value.encode("utf-8", "surrogatepass")
    array = np.asarray(value)
    if array.dtype.kind in "OSU":
        return b"t" + "\x1f".join(str(v) for v in array.ravel()).encode("utf-8", "surrogatepass")
    return f"n{array.dtype.str}{array.shape}".encode() + np.ascontiguousarray(array).tobytes()


def content_digest(ds: xr.Dataset) -> str:
    """SHA-256 of a dataset as read from a file: every variable (name, dimensions,
    attributes, values) and every global attribute except ``content_sha256``."""
    import hashlib

    h = hashlib.sha256()
    for name in sorted(map(str, ds.variables)):
        var = ds.variables[name]
        h.update(b"\0v" + name.encode() + b"\0" + " ".join(map(str, var.dims)).encode())
        for key in sorted(map(str, var.attrs)):
            h.update(b"\0a" + key.encode() + b"\0" + _canonical(var.attrs[key]))
        h.update(b"\0d" + _canonical(var.values))
    for key in sorted(map(str, ds.attrs)):
        if key != CHECKSUM_ATTR:
            h.update(b"\0g" + key.encode() + b"\0" + _canonical(ds.attrs[key]))
    return h.hexdigest()


def _add_checksum(path: Path) -> None:
    """Read a freshly written file back and stamp it with :func:`content_digest`."""
    import netCDF4

    digest = content_digest(_load(path))
    with netCDF4.Dataset(path, mode="a") as nc:
        nc.setncattr(CHECKSUM_ATTR, digest)


# ---------------------------------------------------------------------------
# VTK particle snapshots
# ---------------------------------------------------------------------------


def _vtk_array(name: str, values: Any, n: int) -> np.ndarray | tuple[np.ndarray, ...]:
    """Convert one point field to what pyevtk expects (contiguous float64/int32)."""
    array = np.asarray(values)
    if array.dtype == bool or np.issubdtype(array.dtype, np.integer):
        if array.size and (
            array.min() < np.iinfo(np.int32).min or array.max() > np.iinfo(np.int32).max
        ):
            raise ValueError(f"field {name!r} does not fit in int32")
        array = array.astype(np.int32)
    elif np.issubdtype(array.dtype, np.floating):
        array = array.astype(np.float64)
    else:
        raise TypeError(f"field {name!r} must be numeric, got dtype {array.dtype}")
    if array.shape == (n,):
        return np.ascontiguousarray(array)
    if array.ndim == 2 and array.shape[0] == n and array.shape[1] in (2, 3):
        if array.shape[1] == 2:  # (x, z) components in the 2-D plane; y = 0
            zeros = np.zeros(n, dtype=array.dtype)
            return (np.ascontiguousarray(array[:, 0]), zeros, np.ascontiguousarray(array[:, 1]))
        return tuple(np.ascontiguousarray(array[:, k]) for k in range(3))
    raise ValueError(
        f"field {name!r} has shape {array.shape}; expected ({n},), ({n}, 2) or ({n}, 3)"
    )


class VTKWriter:
    """Write particle snapshots as ``.vtu`` point clouds plus a ParaView ``.pvd``.

    Snapshots are numbered ``{prefix}_000000.vtu``, ``{prefix}_000001.vtu``, ...
    The collection ``{prefix}.pvd`` is rewritten (atomically) after every
    snapshot, so an interrupted run still leaves a usable collection.

    Parameters
    ----------
    directory : str or os.PathLike
        Output directory (created if missing).
    prefix : str
        File-name prefix of the snapshots and the collection.
    resume_after : float, optional
        When resuming a run from a checkpoint at this time: keep the entries of
        an existing ``{prefix}.pvd`` with timestep ``<= resume_after`` and
        continue numbering after them. By default an existing collection is
        replaced.

    Examples
    --------
    >>> with VTKWriter("out/vtk", "particles") as vtk:  # doctest: +SKIP
    ...     vtk.write(t, x, z, {"pressure": p, "velocity": v})
    """

    def __init__(
        self,
        directory: str | os.PathLike[str],
        prefix: str,
        *,
        resume_after: float | None = None,
    ) -> None:
        if not prefix or os.sep in prefix or (os.altsep and os.altsep in prefix):
            raise ValueError(f"prefix must be a plain file-name stem, got {prefix!r}")
        self.directory = Path(directory)
        self.prefix = prefix
        self.directory.mkdir(parents=True, exist_ok=True)
        self._entries: list[tuple[float, str]] = []
        self._closed = False
        if resume_after is not None and self.pvd_path.exists():
            self._entries = [(t, f) for t, f in self._read_pvd(self.pvd_path) if t <= resume_after]

    @property
    def pvd_path(self) -> Path:
        """Path of the ParaView collection file."""
        return self.directory / f"{self.prefix}.pvd"

    @property
    def n_written(self) -> int:
        """Number of snapshots listed in the collection."""
        return len(self._entries)

    def write(
        self,
        time: float,
        x: np.ndarray,
        z: np.ndarray,
        fields: Mapping[str, np.ndarray] | None = None,
    ) -> Path:
        """Write one snapshot and update the collection.

        Parameters
        ----------
        time : float
            Simulated time of the snapshot in s.
        x, z : numpy.ndarray, shape (n,)
            Particle positions in m; the VTK ``y`` coordinate is zero.
        fields : mapping of str to numpy.ndarray, optional
            Point data. Shape ``(n,)`` for scalars, ``(n, 2)`` for vectors in
            the x-z plane (written with a zero y component) or ``(n, 3)``.
            Integer and boolean fields are written as int32, others as float64.

        Returns
        -------
        pathlib.Path
            Path of the ``.vtu`` file written.
        """
        from pyevtk.hl import pointsToVTK

        if self._closed:
            raise RuntimeError(f"VTKWriter for {self.pvd_path} is closed")
        xs = np.ascontiguousarray(np.asarray(x, dtype=np.float64).reshape(-1))
        zs = np.ascontiguousarray(np.asarray(z, dtype=np.float64).reshape(-1))
        if xs.shape != zs.shape:
            raise ValueError(f"x and z differ in length: {xs.size} vs {zs.size}")
        n = xs.size
        ys = np.zeros(n, dtype=np.float64)
        data = {
            str(name): _vtk_array(str(name), values, n) for name, values in (fields or {}).items()
        }

        stem = self.directory / f"{self.prefix}_{len(self._entries):06d}"
        written = Path(pointsToVTK(str(stem), xs, ys, zs, data=data or None))
        self._entries.append((float(time), written.name))
        self._write_pvd()
        return written

    def close(self) -> None:
        """Write the final collection; further :meth:`write` calls are refused."""
        if not self._closed:
            self._write_pvd()
            self._closed = True

    def __enter__(self) -> VTKWriter:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _write_pvd(self) -> None:
        root = ET.Element(
            "VTKFile",
            type="Collection",
            version="0.1",
            byte_order="LittleEndian" if sys.byteorder == "little" else "BigEndian",
        )
        collection = ET.SubElement(root, "Collection")
        for time, name in self._entries:
            ET.SubElement(collection, "DataSet", timestep=repr(time), group="", part="0", file=name)
        ET.indent(root)
        tmp = self.directory / f".{self.pvd_path.name}.tmp-{os.getpid()}"
        try:
            ET.ElementTree(root).write(tmp, encoding="utf-8", xml_declaration=True)
            os.replace(tmp, self.pvd_path)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise

    @staticmethod
    def _read_pvd(path: Path) -> list[tuple[float, str]]:
        root = ET.parse(path).getroot()
        return [(float(ds.attrib["timestep"]), ds.attrib["file"]) for ds in root.iter("DataSet")]
