"""Where a command writes, checked before it starts: every ``--out`` folder and output file.

Every command's output options are parsed with :func:`check_folder` or :func:`check_file`
(argparse ``type=``), so an output that cannot be written is refused at once -- before minutes of work
are lost -- with exit status 2 and one line that names the path and the reason (argparse's
convention for a bad argument; ``cross_check.__main__`` prints it on one line):

* an existing file where a folder is wanted, or a folder where a file is wanted;
* a folder that is not writable: ``os.access`` says no, its mode bits grant no write at all
  (root may write anywhere, but a folder made read-only is the user's statement: ``chmod a-w``
  is honoured for every user), or a probe file cannot be created in it (a read-only mount,
  a virtual file system such as ``/proc`` or ``/sys``);
* a path whose nearest existing ancestor is a file, or is such a folder.

Nothing is created by the check but the probe file, removed at once: a folder that does not
exist yet is made by the command when it writes.  What the check cannot see (the disk filling
up, a folder removed meanwhile) is caught where it happens: ``cross_check.__main__`` turns an
``OSError`` naming a file into the same one line and exit status 2.
"""
from __future__ import annotations

import argparse
import os
import pathlib
import stat
import tempfile


class Unwritable(argparse.ArgumentTypeError):
    """An output path that cannot be written (argparse reports it as a bad argument)."""


def _existing_ancestor(path: pathlib.Path) -> pathlib.Path:
    """The path itself if it exists, else its nearest existing ancestor."""
    probe = path
    while not os.path.lexists(probe):
        parent = probe.parent
        if parent == probe:
            break
        probe = parent
    return probe


def _why_not_writable(folder: pathlib.Path) -> str | None:
    """None if files can be created in the existing ``folder``, else the reason."""
    try:
        mode = folder.stat().st_mode
    except OSError as exc:
        return exc.strerror or str(exc)
    if not stat.S_ISDIR(mode):
        return f"{folder} is not a folder"
    if not mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH) or not os.access(folder, os.W_OK | os.X_OK):
        return f"{folder} is read-only (permission denied)"
    try:
        fd, name = tempfile.mkstemp(prefix=".write-probe-", dir=folder)
    except OSError as exc:
        return f"{folder}: {exc.strerror or exc}"
    os.close(fd)
    os.unlink(name)
    return None


def check_folder(text) -> pathlib.Path:
    """The folder ``text`` as a path, if it is a folder that files can be written into or one
    that can be made; else :class:`Unwritable` naming the path and the reason."""
    path = pathlib.Path(text).expanduser()
    if os.path.lexists(path) and not path.is_dir():
        raise Unwritable(f"cannot write to {str(text)!r}: it is a file, not a folder")
    why = _why_not_writable(_existing_ancestor(path.absolute()))
    if why is not None:
        raise Unwritable(f"cannot write to {str(text)!r}: {why}")
    return path


def check_file(text) -> pathlib.Path:
    """The output file ``text`` as a path, if it can be written (an existing writable file, or a
    new one in a folder that can be written or made); else :class:`Unwritable`."""
    path = pathlib.Path(text).expanduser()
    if path.is_dir():
        raise Unwritable(f"cannot write to {str(text)!r}: it is a folder, not a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise Unwritable(f"cannot write to {str(text)!r}: the file is read-only (permission denied)")
    why = _why_not_writable(_existing_ancestor(path.absolute().parent))
    if why is not None:
        raise Unwritable(f"cannot write to {str(text)!r}: {why}")
    return path
