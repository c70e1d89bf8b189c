"""Sources, compilation and the ``.fmu`` archive (private; the API is in :mod:`bondgraph.fmu`)."""

from __future__ import annotations

import hashlib
import importlib.util
import io
import os
import platform
import shlex
import shutil
import subprocess
import sys
import tempfile
import uuid
import zipfile
from pathlib import Path
from typing import Mapping, Optional, Sequence

from ..errors import BondGraphError

__all__ = ["FMUError", "standard_headers", "platform_folder", "library_suffix", "compile_library",
           "zip_archive", "token_for"]


class FMUError(BondGraphError, ValueError):
    """An FMU cannot be made: the model cannot be one, a bad option, no compiler, a failed build."""


_HEADERS = {2: ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
            3: ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")}


def standard_headers(fmi: int) -> dict[str, bytes]:
    """The FMI standard's header files, from the installed ``fmpy`` package (``fmpy/c-code``).

    Raises
    ------
    FMUError
        When fmpy is not installed (``pip install bondgraph[fmu]``) or lacks a header.
    """
    spec = importlib.util.find_spec("fmpy")
    folders = list(spec.submodule_search_locations or []) if spec is not None else []
    if not folders:
        raise FMUError("building an FMU needs the FMI header files that the fmpy package ships; "
                       "install it with: pip install 'bondgraph[fmu]' (or pip install fmpy)")
    out = {}
    for name in _HEADERS[fmi]:
        path = Path(folders[0], "c-code", name)
        try:
            out[name] = path.read_bytes()
        except OSError as exc:
            raise FMUError(f"the FMI header '{path}' cannot be read ({exc.strerror or exc}); "
                           "reinstall fmpy") from None
    return out


def _machine() -> str:
    machine = platform.machine().lower()
    if machine in ("aarch64", "arm64"):
        return "aarch64"
    if machine in ("amd64", "x86_64", "x86", "i386", "i686", "x86pc"):
        return "x86_64" if sys.maxsize > 2 ** 32 else "x86"
    raise FMUError(f"no FMI platform name for the machine {platform.machine()!r}; "
                   "build a source-only FMU (binary=False) and compile it where it runs")


def _system() -> str:
    if sys.platform.startswith("linux"):
        return "linux"
    if sys.platform.startswith("darwin"):
        return "darwin"
    raise FMUError(f"binaries are built on Linux and macOS only (this is {sys.platform!r}); "
                   "build a source-only FMU (binary=False) and compile it with the importing tool")


def platform_folder(fmi: int) -> str:
    """``binaries/`` sub-folder for this machine: ``linux64`` (FMI 2), ``x86_64-linux`` (FMI 3)..."""
    machine, system = _machine(), _system()
    if fmi == 2:
        return system + ("32" if machine == "x86" else "64")
    return f"{machine}-{system}"


def library_suffix() -> str:
    return ".dylib" if _system() == "darwin" else ".so"


def _compiler(cc: Optional[str]) -> list[str]:
    given = cc if cc is not None else os.environ.get("CC")
    if given:
        words = shlex.split(given)
        if words and shutil.which(words[0]):
            return words
        raise FMUError(f"the C compiler {given!r} was not found")
    for name in ("cc", "gcc", "clang"):
        found = shutil.which(name)
        if found:
            return [found]
    raise FMUError("no C compiler found (cc, gcc or clang on PATH, or the CC environment variable); "
                   "install one, or build a source-only FMU (binary=False)")


#: compiler options of the binary (the sources also build with -Wall -Wextra -pedantic)
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-fvisibility=hidden")


def compile_library(sources: Mapping[str, bytes], c_files: Sequence[str], output: str, *,
                    cc: Optional[str] = None, extra: Sequence[str] = ()) -> bytes:
    """Compile ``c_files`` (written with every file of ``sources`` into a temporary folder).

    Returns
    -------
    bytes
        The shared library.

    Raises
    ------
    FMUError
        No compiler, or the compiler failed (its messages in the error, cut to 4000 characters).
    """
    command = _compiler(cc)
    with tempfile.TemporaryDirectory(prefix="bondgraph-fmu-") as tmp:
        for name, data in sources.items():
            Path(tmp, name).write_bytes(data)
        # relative names, run in the folder: no temporary path ends up in the binary
        argv = [*command, *CFLAGS, *extra, "-I.", "-o", output, *c_files, "-lm"]
        done = _run_compiler(argv, tmp, command[0])
        if done.returncode != 0:
            messages = (done.stderr or done.stdout).strip()
            if len(messages) > 4000:
                messages = "...\n" + messages[-4000:]
            raise FMUError(f"the C compiler failed (exit status {done.returncode}):\n{messages}")
        try:
            return Path(tmp, output).read_bytes()
        except OSError:
            raise FMUError(f"the C compiler {command[0]!r} exited successfully but wrote no "
                           f"{output}: is it a C compiler? (command: {' '.join(command)})") from None


def _run_compiler(argv: Sequence[str], folder: str, name: str) -> "subprocess.CompletedProcess[str]":
    """Run the compiler in its own process group, killed with everything it started on any way out.

    An interrupt, SIGTERM (raised as an interrupt by the command line) or the
    30-minute timeout kills the group (the driver and its ``cc1``/``ld``)
    and waits for it, so the temporary folder is removed with no orphan
    still writing into it; the compiler's temporary files go to that folder too.

    Examples
    --------
    >>> import sys, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     done = _run_compiler([sys.executable, "-c", "import os; print(os.environ['TMPDIR'])"],
    ...                          d, "python")
    ...     done.stdout.strip() == d
    True
    """
    import signal

    try:
        # the compiler's own temporary files (gcc's ccXXXX.s, .o) in the build folder, which is
        # removed on every way out: a killed compiler cannot leave them in the system's TMPDIR
        proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                cwd=folder, start_new_session=True,
                                env=dict(os.environ, TMPDIR=folder, TMP=folder, TEMP=folder))
    except OSError as exc:
        raise FMUError(f"cannot run the C compiler {name!r}: {exc.strerror or exc}") from None
    try:
        out, err = proc.communicate(timeout=1800)
    except BaseException as exc:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (OSError, AttributeError):
            proc.kill()
        proc.wait()
        if isinstance(exc, subprocess.TimeoutExpired):
            raise FMUError("the C compiler took more than 30 minutes") from None
        raise
    return subprocess.CompletedProcess(argv, proc.returncode, out, err)


def token_for(*parts: bytes) -> str:
    """A GUID-formatted token, the digest of ``parts``: the same FMU gets the same token."""
    digest = hashlib.sha256()
    for part in parts:
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    return "{" + str(uuid.UUID(bytes=digest.digest()[:16], version=4)) + "}"


def zip_archive(files: Mapping[str, bytes]) -> bytes:
    """The archive's bytes: fixed time stamps, so equal content gives an equal file."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in files.items():
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o755 if name.startswith("binaries/") else 0o644) << 16
            zf.writestr(info, data)
    return buffer.getvalue()
