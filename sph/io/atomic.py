"""One atomic-write helper for every file the project writes (netCDF results, checkpoints):
the content goes to a hidden temporary file ``.{name}.tmp-{pid}`` beside the target, is
flushed to disk and renamed onto it (atomic on POSIX), so that the target is either the old
file or the complete new one. On any failure the temporary file is removed, the old file is
left untouched and an :class:`OutputWriteError` names the file.
"""

from __future__ import annotations

import errno
import os
from collections.abc import Callable
from pathlib import Path


class OutputWriteError(OSError):
    """A result file could not be written (unwritable directory, disk full, ...).

    The message always names the file that was being written. ``errno`` is copied from the
    underlying error where there is one.
    """


def temporary_name(path: Path) -> Path:
    return path.parent / f".{path.name}.tmp-{os.getpid()}"


def fsync_path(path: Path, *, directory: bool = False) -> None:
    """Flush a file (errors raise) or a directory (best effort: not supported everywhere)
    to disk."""
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        if directory:
            return
        raise
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


def write_error(path: Path, exc: BaseException, what: str, action: str = "") -> OutputWriteError:
    """An :class:`OutputWriteError` naming ``path`` for the failure ``exc``."""
    code = getattr(exc, "errno", None)
    if isinstance(code, int) and code > 0:
        reason = os.strerror(code)
    else:
        code = None
        reason = str(exc) or type(exc).__name__
    if code == errno.ENOSPC:
        reason += " (disk full)"
    if action:
        reason = f"{action}: {reason}"
    message = f"cannot write {what} {str(path)!r}: {reason}"
    return OutputWriteError(code, message) if code is not None else OutputWriteError(message)


def write_atomic(path: str | os.PathLike[str], write: Callable[[Path], None], what: str,
                 is_write_error: Callable[[BaseException], bool] = lambda e: False) -> Path:
    """Write ``path`` atomically: ``write(tmp)`` fills the temporary file (and may read it
    back), which is then flushed and renamed onto ``path``.

    ``what`` names the kind of file in error messages ("netCDF file", "checkpoint");
    ``is_write_error`` marks further exceptions of ``write`` (besides :class:`OSError`) that
    mean the file could not be written. Missing parent directories are created.

    Raises
    ------
    OutputWriteError
        The directory cannot be created or written, the disk is full, or ``write`` failed
        with an error that ``is_write_error`` accepts.
    """
    path = Path(path)
    parent = path.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise write_error(path, exc, what, f"cannot create directory {str(parent)!r}") from exc
    tmp = temporary_name(path.absolute())
    try:
        write(tmp)
        fsync_path(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        if isinstance(exc, OSError) or is_write_error(exc):
            raise write_error(path, exc, what) from exc
        raise
    fsync_path(parent, directory=True)
    return path
