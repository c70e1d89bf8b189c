"""Issue 23, items 2, 5, 13: what sits at an output path survives; SIGTERM leaves nothing.

Audit C08 (a device node replaced by a JSON file), C28/C29 (symlinks
replaced), C30 (a 0600 file made 0644), C32/C33 (SIGTERM left a temporary
file, an FMU build folder and an orphaned compiler), K01 (a .c/.h pair mixed
by two writers).
"""

import json
import os
import signal
import socket
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from bondgraph.export import ExportError, export_json
from bondgraph._support.files import atomic_write_many
from bondgraph.numeric import NumericStateSpace

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


@pytest.fixture
def plant():
    return NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",), {"k": 1.0}, "lag")


def _doc(text):
    doc = json.loads(text)
    assert doc["format"] == "bondgraph-statespace" and doc["A"] == [[-1.0]]
    return doc


def test_symlink_is_kept_and_its_target_replaced(tmp_path, plant):
    (tmp_path / "results").mkdir()
    real = tmp_path / "results" / "out.json"
    real.write_text("old")
    link = tmp_path / "out.json"
    link.symlink_to(Path("results") / "out.json")
    export_json(plant, link)
    assert link.is_symlink() and os.readlink(link) == str(Path("results") / "out.json")
    _doc(real.read_text())
    assert sorted(p.name for p in (tmp_path / "results").iterdir()) == ["out.json"]


def test_dangling_symlink_creates_its_target(tmp_path, plant):
    link = tmp_path / "out.json"
    link.symlink_to("made.json")
    export_json(plant, link)
    assert link.is_symlink()
    _doc((tmp_path / "made.json").read_text())


def test_fifo_is_written_through_and_kept(tmp_path, plant):
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()))
    reader.start()
    export_json(plant, fifo)
    reader.join(timeout=30)
    assert not reader.is_alive()
    _doc(got[0])
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.json"]


@pytest.mark.skipif(os.geteuid() != 0, reason="mknod of a character device needs root")
def test_private_device_node_is_kept(tmp_path, plant):
    """A private mknod copy of /dev/null (never the real one): written through, still a device."""
    node = tmp_path / "devnull"
    os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    export_json(plant, node)
    info = os.lstat(node)
    assert stat.S_ISCHR(info.st_mode) and os.major(info.st_rdev) == 1 and os.minor(info.st_rdev) == 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["devnull"]


def test_socket_is_refused(tmp_path, plant):
    path = tmp_path / "s.json"
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(path))
        with pytest.raises(ExportError, match=r"s\.json': it is a socket, not a regular file"):
            export_json(plant, path)
        assert stat.S_ISSOCK(os.lstat(path).st_mode)


def test_private_file_keeps_its_mode(tmp_path, plant):
    """C30: an existing 0600 file came back 0644 (world-readable)."""
    path = tmp_path / "priv.json"
    path.write_text("secret")
    path.chmod(0o600)
    export_json(plant, path)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    _doc(path.read_text())
    new = tmp_path / "new.json"
    export_json(plant, new)
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(new.stat().st_mode) == 0o666 & ~umask


def test_pair_takes_the_folder_lock(tmp_path):
    """K01: the pair is written under an exclusive flock of its folder; a held lock makes it wait."""
    import fcntl

    fd = os.open(tmp_path, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    done = threading.Event()

    def write():
        atomic_write_many([(tmp_path / "p.c", lambda f: f.write("A")),
                           (tmp_path / "p.h", lambda f: f.write("A"))], binary=False)
        done.set()

    worker = threading.Thread(target=write)
    worker.start()
    assert not done.wait(0.5), "the pair was written while another writer held the folder"
    assert not (tmp_path / "p.c").exists()
    os.close(fd)
    assert done.wait(30)
    worker.join()
    assert (tmp_path / "p.c").read_text() == (tmp_path / "p.h").read_text() == "A"


# ------------------------------------------------------------------ signals
EXPORT_SLOWLY = """
import os, sys, time
import bondgraph.files as files
real_fsync = os.fsync
def slow_fsync(fd):
    real_fsync(fd)
    print("WRITING", flush=True, file=sys.stderr)
    time.sleep(60)
files.os.fsync = slow_fsync
from bondgraph.cli import main
sys.exit(main(sys.argv[1:]))
"""

MSD = """\
import bondgraph as bg

def model():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"x": bg.displacement("c")},
                              parameters={"m": 2.0, "b": 6.0, "c": 0.25})
"""


def _wait_for(proc, marker, timeout=120):
    t0 = time.time()
    while time.time() - t0 < timeout:
        line = proc.stderr.readline()
        if marker in line:
            return
        if not line and proc.poll() is not None:
            break
    proc.kill()
    raise AssertionError(f"never saw {marker!r}: exit {proc.poll()}")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_signal_during_export_leaves_nothing(tmp_path, sig):
    """C32: SIGTERM while the temporary file was written left out/.big.json.XXXX.tmp."""
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    out = tmp_path / "out"
    out.mkdir()
    # the child must not inherit an ignored SIGHUP (a suite started under nohup): the command
    # line deliberately leaves an ignored signal ignored
    proc = subprocess.Popen([sys.executable, "-c", EXPORT_SLOWLY, "export", str(model), "-o",
                             str(out / "big.json")], stderr=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True, env=ENV,
                            preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL))
    _wait_for(proc, "WRITING")
    assert [p.name for p in out.iterdir()][0].startswith(".big.json.")   # the temporary file
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig
    assert f"error: terminated by {signal.Signals(sig).name}" in err
    assert list(out.iterdir()) == []


FAKE_CC = """#!/bin/sh
# a compiler that never finishes: it and its child write into the build folder
echo $$ > "$MARKER.cc"
(while true; do echo x >> child.out; sleep 0.05; done) &
echo $! > "$MARKER.child"
echo started > "$MARKER"
sleep 120
"""


def _gone(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    with open(f"/proc/{pid}/stat") as fh:           # a zombie waiting for its parent is gone too
        return fh.read().split()[2] == "Z"


def test_sigterm_during_fmu_build_leaves_nothing(tmp_path):
    """C33: SIGTERM left $TMPDIR/bondgraph-fmu-XXXX/ and an orphaned compiler writing into it."""
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    cc = tmp_path / "fakecc"
    cc.write_text(FAKE_CC)
    cc.chmod(0o755)
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    marker = tmp_path / "marker"
    env = {**ENV, "CC": str(cc), "TMPDIR": str(tmp), "MARKER": str(marker)}
    proc = subprocess.Popen([sys.executable, "-m", "bondgraph", "export", str(model), "--format", "fmu",
                             "-o", str(tmp_path / "m.fmu")], stderr=subprocess.PIPE, text=True, env=env)
    t0 = time.time()
    while not marker.exists() and time.time() - t0 < 120 and proc.poll() is None:
        time.sleep(0.05)
    assert marker.exists(), f"the compiler never started: {proc.communicate()[1]}"
    cc_pid = int(Path(f"{marker}.cc").read_text())
    child_pid = int(Path(f"{marker}.child").read_text())
    assert [p.name for p in tmp.iterdir()][0].startswith("bondgraph-fmu-")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    assert list(tmp.iterdir()) == [] and not (tmp_path / "m.fmu").exists()
    time.sleep(0.3)
    assert _gone(cc_pid) and _gone(child_pid), "the compiler (or its child) outlived the build"


def test_compiler_that_writes_no_library_is_an_fmu_error(tmp_path):
    """U17: a 'compiler' that exits 0 without output gave a raw FileNotFoundError."""
    from bondgraph.fmu import FMUError
    from bondgraph.fmu._build import compile_library

    with pytest.raises(FMUError, match="exited successfully but wrote no lib.so"):
        compile_library({"a.c": b"int x;\n"}, ["a.c"], "lib.so", cc="true")
