"""The files of the SpongeCake scripts: inputs opened with errors that name them, outputs
checked against every input before any work, and outputs written whole or not at all
(README, "What mcref guarantees about your data": bad input gets one line naming the
file, no input is touched, no half-written file is left and a good file is never
replaced by a bad one).
"""
import contextlib
import os
import tempfile

import h5py


def open_hdf5(path):
    """h5py.File(path, "r"), or a ValueError naming the file (h5py's own message does not)."""
    if not os.path.exists(path):
        raise ValueError(f"{path}: no such file")
    if os.path.isdir(path):
        raise ValueError(f"{path}: is a directory (expected an HDF5 file)")
    try:
        return h5py.File(path, "r")
    except OSError as e:
        raise ValueError(f"{path}: cannot be read as HDF5 ({e})") from None


def same_file(a, b):
    """Whether the paths name the same file: through symbolic links and '..' (realpath) or,
    when both exist, as the same inode (hard links)."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def check_outputs(outputs, inputs):
    """Before any work: every output (key, path) can be written as a regular file, is none of
    the inputs (key, path; None skipped), and no two outputs are the same file."""
    for n, (key, path) in enumerate(outputs):
        parent = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(parent):
            raise ValueError(f"{key} {path}: directory {parent} does not exist")
        if os.path.isdir(path):
            raise ValueError(f"{key} {path}: is a directory (allowed: a file to write)")
        if os.path.lexists(path) and not os.path.isfile(path):
            raise ValueError(f"{key} {path}: exists and is not a regular file (allowed: a file to write)")
        if not os.access(parent, os.W_OK | os.X_OK):
            raise ValueError(f"{key} {path}: directory {parent} is not writable")
        for in_key, in_path in inputs:
            if in_path is not None and same_file(path, in_path):
                raise ValueError(f"{key} {path}: is the input {in_key} {in_path} (allowed: a file that is none of "
                                 "the inputs)")
        for other_key, other in outputs[:n]:
            if same_file(path, other):
                raise ValueError(f"{key} {path}: is also the output {other_key} {other}")


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_output(path):
    """Yields a new temporary file beside `path` (a unique name, so it clobbers nothing) to
    write; renames it onto `path` when the block succeeds, removes it when it fails."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)), prefix=f".{os.path.basename(path)}.",
                               suffix=".tmp")
    os.close(fd)
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes it 0600; an output gets the usual mode
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
