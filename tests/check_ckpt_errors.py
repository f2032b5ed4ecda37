"""check_ckpt_errors.py -- checkpoints against bad disks and bad files (issue 5):
an output directory under a regular file (ENOTDIR) and a checkpoint that cannot be
written (its temporary name taken by a directory) fail with status 2 and a message
naming the path, earlier output intact; a file-size limit (RLIMIT_FSIZE with SIGXFSZ
ignored: EFBIG, as a full disk) stops the run with status 2, leaves the previous
checkpoint valid, and resuming without the limit ends identical to an uninterrupted
run; a frames.h5 (the index) damaged by hand after its checkpoint is kept as
frames.h5.damaged (its segments as frames.d.damaged) and the resume still succeeds; a
segment damaged after the checkpoint is dropped and the resume ends identical; `--resume` with a scene or --set is refused; `--resume` and `esfera info` on a missing, empty, truncated, corrupted, foreign
(text, HDF5) checkpoint, or one from a build with another esf_contact_hist layout, exit
2 naming the cause; so does `--resume` from a checkpoint that passes its checksums but
does not fit its scene or itself (issue 27: the ledger flag, counters out of range,
2^40 frames, t against step x dt, particles' radii and ids, list order, non-finite
values). Usage: check_ckpt_errors.py ESFERA"""
import os
import re
import resource
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

import h5py

from ckpt_common import ERK, ERK_TABLE, esfera, identical, run_ok, write_scene
from pycheck import check, finish


def expect_fail(exe, args, words, what, **kw):
    try:
        r = esfera(exe, *args, **kw)
    except subprocess.TimeoutExpired:
        check(False, f"{what}: did not end within {kw.get('timeout')} s")
        return None
    ok = r.returncode == 2 and all(w in r.stderr for w in words)
    check(ok, f"{what}: exit {r.returncode}, stderr {r.stderr!r} (wanted {words})")
    print(f"{what}: exit {r.returncode}: {r.stderr.strip().splitlines()[0] if r.stderr else ''}")
    return r


def sections(data):
    """(tag, offset of payload, length) of each section."""
    pos, out = 16, []
    while pos < len(data):
        tag = data[pos:pos + 8].rstrip(b"\0").decode()
        (n,) = struct.unpack("<Q", data[pos + 8:pos + 16])
        out.append((tag, pos + 16, n))
        pos += 16 + n + 4
    return out


def patch(data, tag, fn):
    """data with section tag's payload replaced by fn(bytearray payload), its CRC
    recomputed: a file that passes its checksums."""
    for t, off, n in sections(data):
        if t == tag:
            new = bytes(fn(bytearray(data[off:off + n])))
            return (data[:off - 8] + struct.pack("<Q", len(new)) + new +
                    struct.pack("<I", zlib.crc32(new)) + data[off + n + 4:])
    raise KeyError(tag)


def put(fmt, off, value):
    def fn(b):
        struct.pack_into(fmt, b, off, value)
        return b
    return fn


def swap_contacts(b):
    """Swaps the first two candidates' a and b (the list's order broken)."""
    m = struct.unpack_from("<Q", b, 0)[0]
    for base in (10, 10 + 4 * m):
        x, y = struct.unpack_from("<II", b, base)
        struct.pack_into("<II", b, base, y, x)
    return b


def len_part(n):
    """Bytes of a PART section of n particles."""
    return 8 + n * (9 + 3 + 3 + 5) * 8 + n * (4 + 8)


def misfits(exe, tmp, scene, ref, data):
    """Checkpoints that pass their checksums but do not fit their scene or themselves
    (issue 27): exit 2 naming the misfit, never a crash, an endless run or a huge
    allocation. Offsets: ck_sim (t, dt, led_time, alpha_r, alpha_t, contacts_sum,
    walls_t, then int64 step, removed, ...), esf_ledger (int on, then doubles),
    esf_ckpt_run (n, next_e, next_f, next_c, psum, then int64 frames, erows, csv_bytes,
    count), PART (u64 n, then x, v, w, f, t, radius, ..., material, id)."""
    n = [struct.unpack_from("<Q", data, o)[0] for t, o, _ in sections(data)
         if t == "PART"][0]
    # a ledger-off checkpoint of the same bed, for the ledger flag set on it
    off = os.path.join(tmp, "ledger_off")
    run_ok(exe, "run", scene, "--out", off, "--quiet", "--set", "output.energy_every=0",
           "--checkpoint-every", "0.02")
    data_off = open(os.path.join(off, "checkpoint.esf"), "rb").read()
    # and one of adaptive Dormand-Prince (erk_saved: double h first, ... y)
    erk = os.path.join(tmp, "erk")
    run_ok(exe, "run", scene, "--out", erk, "--quiet", *ERK, "--checkpoint-every", "0.004")
    data_erk = open(os.path.join(erk, "checkpoint.esf"), "rb").read()
    # and one with the scene's Butcher table (esf_butcher last in INTEG: 4 int32, then
    # c[16], b[16], d[16], A[16][16]; b_0 sits 2304 bytes before the end)
    erk_t = os.path.join(tmp, "erk_table")
    run_ok(exe, "run", scene, "--out", erk_t, "--quiet", *ERK_TABLE, "--checkpoint-every",
           "0.004")
    data_erk_t = open(os.path.join(erk_t, "checkpoint.esf"), "rb").read()
    cases = [
        (off, "LEDGER", put("<i", 0, 1), ["energy ledger is on in it, off"],
         "ledger flag set on a scene without the ledger"),
        (ref, "SIM", put("<q", 56, -2**62), ["step -4611686018427387904"],
         "step counter -2^62"),
        (ref, "SIM", put("<q", 56, 10**15), ["out of range"], "step counter 1e15"),
        (ref, "SIM", put("<d", 0, float("nan")), ["not finite"], "t NaN"),
        (ref, "SIM", put("<d", 0, 0.0123), ["is not step"], "t not step x dt"),
        (ref, "SIM", put("<q", 64, 7), ["removed do not make"], "removed count"),
        (ref, "RUN", put("<q", 40, 2**40), ["1099511627776 frames"], "2^40 frames"),
        (ref, "RUN", put("<q", 48, 2**40), ["1099511627776 energy rows"],
         "2^40 energy rows"),
        (ref, "RUN", put("<q", 0, 5), ["loop counter"], "loop counter"),
        (ref, "RUN", put("<q", 56, -1), ["energy.csv"], "energy.csv size with a ledger"),
        (ref, "RUN", put("<d", 8, float("nan")), ["not a number"], "NaN schedule"),
        (ref, "PART", put("<d", 8 + 8 * 15 * n, 1.0), ["another radius"],
         "a particle's radius"),
        (ref, "PART", put("<d", 8, float("inf")), ["not finite"], "a position inf"),
        (ref, "PART", put("<q", len_part(n) - 8, 0), ["unknown to the scene or repeated"],
         "a repeated particle id"),
        (ref, "CONTPP", swap_contacts, ["order of its build"], "pair list unsorted"),
        (ref, "LEDGER", put("<d", 120, float("inf")), ["non-finite"], "ledger e0 inf"),
        (ref, "WALLS", put("<d", 12, float("nan")), ["placement"], "wall mark NaN"),
        (erk, "INTEG", put("<d", 0, -1.0), ["saved step, times or counters"],
         "adaptive ERK: step size -1"),
        (erk, "INTEG", put("<d", 200, float("nan")), ["ODE state is not finite"],
         "adaptive ERK: NaN in y"),
        (erk_t, "INTEG", put("<d", -2304, 0.25), ["Butcher table differs"],
         "the scene's Butcher table: b_0 changed"),
    ]
    for k, (src, tag, fn, words, what) in enumerate(cases):
        bad = os.path.join(tmp, f"misfit{k}")  # the whole output: a resume gets past
        shutil.copytree(src, bad)             # reopening it to the checkpoint itself
        ck = {off: data_off, erk: data_erk, erk_t: data_erk_t}.get(src, data)
        with open(os.path.join(bad, "checkpoint.esf"), "wb") as fh:
            fh.write(patch(ck, tag, fn))
        expect_fail(exe, ["run", "--resume", bad, "--quiet"], words, "misfit: " + what,
                    timeout=60)


def main():
    exe = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="esf_ckerr_")
    try:
        scene = write_scene(tmp)
        short = ["--set", "run.duration=0.02"]
        # output directory under a regular file
        plain = os.path.join(tmp, "plain_file")
        open(plain, "w").write("x")
        expect_fail(exe, ["run", scene, "--out", plain + "/sub", "--quiet", *short],
                    [plain, "Not a directory"], "output under a regular file")

        # a checkpoint that cannot be written: earlier output intact
        out = os.path.join(tmp, "blocked")
        os.makedirs(os.path.join(out, "checkpoint.esf.tmp"))
        expect_fail(exe, ["run", scene, "--out", out, "--quiet", "--checkpoint-every",
                          "0.005", *short], ["checkpoint.esf", "Is a directory"],
                    "checkpoint path blocked")
        with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
            check(len(f["frames"]) >= 3, "blocked: the frames before it are readable")
        check(not os.path.exists(os.path.join(out, "checkpoint.esf")),
              "blocked: no checkpoint")

        # EFBIG (a full disk): the previous checkpoint stays valid and resumes exactly
        ref = os.path.join(tmp, "ref")
        run_ok(exe, "run", scene, "--out", ref, "--quiet")
        big = os.path.join(tmp, "efbig")
        lim = 100 * 1024  # below the final energy.csv (150 kB); the other files stay under

        def limit():
            resource.setrlimit(resource.RLIMIT_FSIZE, (lim, lim))

        expect_fail(exe, ["run", scene, "--out", big, "--quiet", "--checkpoint-every",
                          "0.004"], ["File too large"], "file-size limit (EFBIG)",
                    preexec_fn=limit)
        r = run_ok(exe, "info", os.path.join(big, "checkpoint.esf"))
        step = [ln for ln in r.stdout.splitlines() if ln.startswith("time: ")]
        run_ok(exe, "run", "--resume", big, "--quiet")
        n, diffs = identical(ref, big)
        check(n > 5 and not diffs, f"EFBIG then resume: output differs: {diffs[:5]}")
        print(f"EFBIG: checkpoint at {step} intact, resumed: {n} frames identical")

        # a frames.h5 damaged after the checkpoint: kept aside, the resume goes on
        dmg = os.path.join(tmp, "damaged")
        shutil.copytree(big, dmg)
        fh5 = os.path.join(dmg, "frames.h5")
        with open(fh5, "r+b") as fh:
            fh.truncate(os.path.getsize(fh5) // 3)
        run_ok(exe, "run", "--resume", dmg, "--quiet")
        log = open(os.path.join(dmg, "log.txt")).read()
        check(os.path.exists(fh5 + ".damaged") and "WARNING" in log and
              "frames.h5.damaged" in log, "damaged frames.h5: kept aside with a warning")
        check(os.path.exists(os.path.join(dmg, "frames.d.damaged", "000000.h5")),
              "damaged frames.h5: its segments kept aside in frames.d.damaged")
        with h5py.File(fh5, "r") as f:
            check(len(f["frames"]) >= 1, "damaged frames.h5: the new file has frames")
        with open(os.path.join(dmg, "energy.csv"), "rb") as fa, \
                open(os.path.join(ref, "energy.csv"), "rb") as fb:
            check(fa.read() == fb.read(), "damaged frames.h5: energy.csv still identical")
        print("damaged frames.h5: resumed, old file kept as frames.h5.damaged")

        # the same, but frames.d.damaged is taken: the resume stops, nothing is lost
        dmg2 = os.path.join(tmp, "damaged2")
        shutil.copytree(big, dmg2)
        fh5 = os.path.join(dmg2, "frames.h5")
        with open(fh5, "r+b") as fh:
            fh.truncate(os.path.getsize(fh5) // 3)
        taken = os.path.join(dmg2, "frames.d.damaged")
        os.makedirs(taken)
        open(os.path.join(taken, "keep"), "w").close()
        segs = sorted(os.listdir(os.path.join(dmg2, "frames.d")))
        r = subprocess.run([exe, "run", "--resume", dmg2, "--quiet"], capture_output=True,
                           text=True)
        check(r.returncode != 0 and "cannot be moved aside" in r.stderr,
              f"frames.d.damaged taken: the resume stops ({r.returncode}: {r.stderr.strip()})")
        check(sorted(os.listdir(os.path.join(dmg2, "frames.d"))) == segs and
              os.path.exists(fh5) and not os.path.exists(fh5 + ".damaged"),
              "frames.d.damaged taken: the segments and the index are left as they were")
        print(f"damaged frames.h5 with frames.d.damaged taken: stopped, {len(segs)} segments kept")

        # a segment damaged after the checkpoint (what a kill in the middle of an HDF5
        # append can leave): the checkpoint's frames are in other, closed segments, so
        # the resume drops it and ends identical to the uninterrupted run
        seg = os.path.join(tmp, "segment")
        run_ok(exe, "run", scene, "--out", seg, "--quiet", "--checkpoint-every", "0.013")
        r = run_ok(exe, "info", os.path.join(seg, "checkpoint.esf"))
        nck = int([ln for ln in r.stdout.splitlines() if ln.startswith("frames: ")][0][8:])
        segs = sorted(os.listdir(os.path.join(seg, "frames.d")))
        after = [f for f in segs if int(f[:-3]) >= nck]
        check(len(after) == 1 and len(segs) > 2,
              f"segments {segs}: one expected after the checkpoint's {nck} frames")
        for f in after:
            path = os.path.join(seg, "frames.d", f)
            with open(path, "r+b") as fh:
                fh.truncate(os.path.getsize(path) // 3)
        run_ok(exe, "run", "--resume", seg, "--quiet")
        n, diffs = identical(ref, seg)
        check(n > 5 and not diffs and not os.path.exists(os.path.join(seg, "frames.h5.damaged")),
              f"segment damaged after the checkpoint: output differs: {diffs[:5]}")
        print(f"segment {after} damaged after the checkpoint ({nck} frames): resumed, "
              f"{n} frames identical")

        # bad checkpoint files
        ck = os.path.join(ref, "checkpoint.esf")
        run_ok(exe, "run", scene, "--out", ref, "--quiet", "--overwrite",
               "--checkpoint-every", "0.02")
        data = open(ck, "rb").read()
        bad = os.path.join(tmp, "bad")
        os.makedirs(bad)
        bck = os.path.join(bad, "checkpoint.esf")

        def trial(content, words, what, info_words=None):
            with open(bck, "wb") as fh:
                fh.write(content)
            expect_fail(exe, ["run", "--resume", bad, "--quiet"], words, "resume " + what)
            if info_words != []:  # info knows foreign files as not HDF5 (or as frames)
                expect_fail(exe, ["info", bck], info_words or words, "info " + what)

        expect_fail(exe, ["run", "--resume", big, "--set", "run.duration=1"],
                    ["--resume DIR continues"], "resume with --set")
        expect_fail(exe, ["run", "--resume", os.path.join(tmp, "nowhere"), "--quiet"],
                    ["cannot open", "nowhere"], "resume missing")
        trial(b"", ["not an esfera checkpoint"], "empty", ["not an HDF5 file"])
        trial(data[: len(data) // 2], ["truncated"], "truncated at the half")
        trial(data[:-3], ["truncated"], "truncated by 3 bytes")
        flip = bytearray(data)
        flip[len(data) // 2] ^= 0x10
        trial(bytes(flip), ["corrupted", "checksum"], "one bit flipped")
        trial(b"name: not a checkpoint\n" * 10, ["not an esfera checkpoint"], "text",
              ["not an HDF5 file"])
        trial(open(os.path.join(ref, "frames.h5"), "rb").read(),
              ["not an esfera checkpoint"], "HDF5 frames file", [])
        # another esf_contact_hist layout (a build with bond fields): refused clearly
        lay = bytearray(data)
        for tag, off, n in sections(data):
            if tag == "LAYOUT":
                text = re.sub(rb"esf_contact_hist \d+: [^\n]*",
                              b"esf_contact_hist 88: xi f64[3], n f64[3], other f64[5]",
                              data[off:off + n])
                lay = bytearray(data[:off - 8] + struct.pack("<Q", len(text)) + text +
                                struct.pack("<I", zlib.crc32(text)) + data[off + n + 4:])
        trial(bytes(lay), ["other record layouts", "other f64[5]"], "other hist layout")
        misfits(exe, tmp, scene, ref, data)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("ckpt_errors")


if __name__ == "__main__":
    sys.exit(main())
