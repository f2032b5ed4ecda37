#!/usr/bin/python3
"""corpus.py -- the fuzzers' seed corpora and dictionaries, built from the repository
(nothing of it is committed but the few fixed files of tests/fuzz/data):

    tests/fuzz/corpus.py ESFERA OUT_DIR

OUT_DIR/scene: every scene of scenes/, tests/bench_poly/ and tests/fuzz/data, and the
    scenes the tests write (YAML in the Python tests' strings, the shell tests'
    here-documents, the C tests' string literals), plus two that name the fixed CSV and
    STL files;
OUT_DIR/set: the --set overrides the tests and docs use, one per file, and some
    combinations, plus overrides of the --set harness's own scene (fuzz_set.c);
OUT_DIR/csv: the fixed CSV, the first rows of the bundled packing, variants (BOM, CRLF,
    comments, materials) and the CSV files under studies/ (their headers are errors);
OUT_DIR/stl: the fixed ASCII STL and binary, CRLF and two-solid variants of it;
OUT_DIR/ckpt: a checkpoint of each tests/fuzz/data/ckpt_*.yaml, written by ESFERA (a
    short run each, a few seconds in all);
OUT_DIR/{yaml,csv,stl,ckpt}.dict: libFuzzer dictionaries (the scene keys and choices
    are read from src/scene/*.c, so the dictionary follows the schema).
Prints the count of seeds per harness."""
import glob
import hashlib
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(ROOT, "tests", "fuzz", "data")


def save(out, name, data):
    if isinstance(data, str):
        data = data.encode()
    os.makedirs(os.path.join(out, name), exist_ok=True)
    h = hashlib.sha1(data).hexdigest()[:16]
    with open(os.path.join(out, name, h), "wb") as f:
        f.write(data)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def c_unescape(s):
    return bytes(s, "utf-8").decode("unicode_escape")


def scenes_in_tests():
    """YAML scenes written by the tests: Python strings, here-documents, C literals."""
    found = []
    for p in glob.glob(os.path.join(ROOT, "tests", "*.py")):
        for m in re.finditer(r'"""(.*?)"""', open(p).read(), re.S):
            if "materials:" in m.group(1):
                found.append(m.group(1))
    for p in glob.glob(os.path.join(ROOT, "tests", "*.sh")):
        text = open(p).read()
        for m in re.finditer(r"<<'?YAML'?\n(.*?)\nYAML\n", text, re.S):
            found.append(re.sub(r"\$[0-9]", "", m.group(1)))
    lit = re.compile(r'^\s*(?:[^"]*=\s*)?"((?:[^"\\]|\\.)*)"\s*[;,)]*\s*$')
    for p in glob.glob(os.path.join(ROOT, "tests", "*.c")):
        run = []
        for line in open(p).read().splitlines() + [""]:
            m = lit.match(line)
            if m:
                run.append(c_unescape(m.group(1)))
                continue
            text = "".join(run)
            run = []
            if "materials:" in text:
                found.append(re.sub(r"%[-+ #0-9.]*(?:l|ll|z)?[dgfeusx]", "1", text))
    return found


EXTRA_SCENES = [
    """name: files
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {file: particles.csv}
  - {file: particles.csv, material: glass}
walls:
  - mesh: {file: tet.stl, scale: 0.01, rotate: {axis: [0, 0, 1], degrees: 30},
           translate: [0, 0, -0.02]}
    material: glass
run: {steps: 10}
""",
    """name: gen
dimension: 2
disk_thickness: 0.001
gravity: [0, 0, -9.81]
materials: {a: {density: 1000, kn: 1.0e4}, b: {density: 2000, kn: 2.0e4}}
particles:
  - generate: random
    region: {min: [0, 0, 0], max: [0.1, 0, 0.1]}
    count: 20
    radius: {values: [0.002, 0.004], fractions: [0.7, 0.3]}
    material: {mix: {a: 1, b: 2}}
walls:
  - screw: {base: [0.05, 0, 0], axis: [0, 0, 1], shaft_radius: 0.005, radius: 0.02,
            pitch: 0.02, turns: 2, segments: 12}
    material: a
    motion: {rotate: {axis: [0, 0, 1], rpm: 60}}
integrator: {method: rk4, dt: auto}
damping: {rayleigh: {zeta: 0.1, frequency: 100}}
run: {duration: 0.001}
""",
]


def set_seeds():
    sets = set()
    for pat in ("tests/*.sh", "tests/*.py", "tests/*.c", "docs/*.md", "studies/*.py",
                "README.md"):
        for p in glob.glob(os.path.join(ROOT, pat)):
            text = open(p).read()
            for m in re.finditer(r"--set[ =]'?([a-z_]+(?:\.[a-z0-9_]+)*=[^ '\"`\n]*)", text):
                sets.add(m.group(1).rstrip(":);,"))
            for m in re.finditer(r"[\"']([a-z_]+(?:\.[a-z0-9_]+)+=[^\"'{}\n]*)[\"']", text):
                sets.add(m.group(1))
    own = ["particles.3.count=20", "particles.3.generate=random", "particles.2.file=tet.stl",
           "walls.2.mesh.file=particles.csv", "walls.1.motion={rotate: {axis: [0,0,1], rpm: 10}}",
           "walls.3.cylinder.segments=3", "fluid.porosity={cell: 0.01}", "events.0.at=0",
           "materials.steel.adhesion.epsilon=0.9", "integrator.method=erk:ARKODE_HEUN_EULER_2_1_2",
           "integrator.rtol=1e-4", "damping.global.auto=true", "dimension=2", "domain=~",
           "particles.0=~", "walls=[]", "mixing.kn=arithmetic", "name='a b'", "x.y.z=1"]
    return sorted(sets) + own


def csv_seeds():
    out = [read(os.path.join(DATA, "particles.csv"))]
    lines = open(os.path.join(ROOT, "scenes", "debris_chute_3d.csv")).read().splitlines()
    out.append("\n".join(lines[:20]) + "\n")
    out += ["\ufeffx,y,z,radius\r\n0,0,0,0.001\r\n1,0,0,0.002",
            "# comment\n\n  x , y , z , radius , wx , wy , wz\n1e-3,2,3,4,5,6,7\n# end\n",
            "radius,material,z,y,x\n0.1,steel,0,0,0\n0.2,glass,1,1,1\n",
            "x,y,z,radius\n0.1,0,0.01,abc\n", "x,y,z\n1,2,3\n", "x,y,z,radius\n"]
    for p in sorted(glob.glob(os.path.join(ROOT, "studies", "results", "*", "*.csv")))[:6]:
        out.append("\n".join(open(p).read().splitlines()[:5]) + "\n")
    return out


def stl_seeds():
    text = open(os.path.join(DATA, "tet.stl")).read()
    tris = [[list(map(float, l.split()[1:])) for l in text.splitlines() if "vertex" in l][k:k + 3]
            for k in range(0, 12, 3)]

    def binary(header, tris):
        b = header.encode().ljust(80, b"\0") + struct.pack("<I", len(tris))
        for t in tris:
            b += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *v) for v in t)
            b += b"\0\0"
        return b
    return [text, text.replace("\n", "\r\n"), text + text.replace("tet", "second"),
            binary("binary tet", tris), binary("solid but binary", tris[:2]),
            binary("one", tris[:1])]


def ckpt_seeds(esfera):
    out = []
    tmp = tempfile.mkdtemp(prefix="esf-corpus-")
    try:
        for scene in sorted(glob.glob(os.path.join(DATA, "ckpt_*.yaml"))):
            d = os.path.join(tmp, os.path.basename(scene))
            r = subprocess.run([esfera, "run", scene, "--out", d, "--quiet", "--threads", "1"],
                               capture_output=True, text=True)
            ck = os.path.join(d, "checkpoint.esf")
            if r.returncode != 0 or not os.path.exists(ck):
                sys.exit(f"corpus.py: {scene} gave no checkpoint: {r.stderr}")
            out.append(read(ck))
    finally:
        shutil.rmtree(tmp)
    return out


def dict_line(tok):
    if isinstance(tok, str):
        tok = tok.encode()
    return '"' + "".join(chr(c) if 32 <= c < 127 and c not in (34, 92) else "\\x%02X" % c
                         for c in tok) + '"'


def yaml_dict():
    words = set()
    for p in glob.glob(os.path.join(ROOT, "src", "scene", "*.c")):
        for m in re.finditer(r"static const char \*const \w+\[\] = \{(.*?)\};",
                             open(p).read(), re.S):
            words.update(re.findall(r'"([^"\\]+)"', m.group(1)))
    words.update(["leapfrog", "verlet", "rk4", "cvode-adams", "erk:ARKODE_DORMAND_PRINCE_7_4_5",
                  "harmonic", "arithmetic", "geometric", "min", "max"])
    syntax = ["---", "...", "- ", ": ", "{", "}", "[", "]", ", ", "&a ", "*a", "!!str ",
              "!!int ", "!!float ", "? ", "|\n", ">\n", "# ", "'", '"', "~", "null", "true",
              "false", "yes", "off", ".inf", "-.inf", ".nan", "1e308", "-1e308", "1e-320",
              "0x10", "0o7", "-0", "9223372036854775807", "18446744073709551616", "1e9",
              "<<: ", "\t", "\n  ", "=", ".0.", "\\u0000", "%YAML 1.1\n", "%TAG ! x\n"]
    return "\n".join(dict_line(w) for w in sorted(words) + syntax) + "\n"


STL_DICT = ["solid", "endsolid", "facet", "normal", "outer", "loop", "vertex", "endloop",
            "endfacet", "nan", "inf", "-inf", "1e308", "1e-308", "0x1p3", "\r\n",
            "\x00\x00\x00\x00", "\x01\x00\x00\x00", "\xff\xff\xff\xff", "\x00\x00\xc0\x7f"]
CSV_DICT = ["x", "y", "z", "radius", "vx", "vy", "vz", "wx", "wy", "wz", "material", "glass",
            "steel", ",", "#", "\r\n", "\xef\xbb\xbf", "nan", "inf", "1e308", "-0", "0x1p-3"]
CKPT_DICT = ["ESFCKPT\x00", "\x04\x03\x02\x01", "\x02\x00\x00\x00", "META\x00\x00\x00\x00",
             "LAYOUT\x00\x00", "SCENE\x00\x00\x00", "SCNPATH\x00", "SETS\x00\x00\x00\x00",
             "METHOD\x00\x00", "SIM\x00\x00\x00\x00\x00", "LEDGER\x00\x00", "RUN\x00\x00\x00\x00\x00",
             "WALLS\x00\x00\x00", "SAND\x00\x00\x00\x00", "MATS\x00\x00\x00\x00",
             "PART\x00\x00\x00\x00", "CONTPP\x00\x00", "CONTPW\x00\x00", "NBREF\x00\x00\x00",
             "NBSKIN\x00\x00", "INTEG\x00\x00\x00", "END\x00\x00\x00\x00\x00",
             "\x00\x00\x00\x00\x00\x00\xf0\x7f", "\x00\x00\x00\x00\x00\x00\xf8\x7f",
             "\xff\xff\xff\xff\xff\xff\xff\xff", "\x00\x00\x00\x00\x00\x00\x00\x80",
             "\x01\x00\x00\x00\x00\x00\x00\x00", "\xff\xff\xff\x7f"]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    esfera, out = sys.argv[1], sys.argv[2]
    if os.path.isdir(out):
        shutil.rmtree(out)
    os.makedirs(out)
    scene_files = (glob.glob(os.path.join(ROOT, "scenes", "*.yaml")) +
                   glob.glob(os.path.join(ROOT, "tests", "bench_poly", "*.yaml")) +
                   glob.glob(os.path.join(DATA, "*.yaml")))
    for p in scene_files:
        save(out, "scene", read(p))
    for s in scenes_in_tests() + EXTRA_SCENES:
        save(out, "scene", s)
    sets = set_seeds()
    for s in sets:
        save(out, "set", s + "\n")
    for k in range(0, len(sets) - 2, 3):  # a few combinations, in order
        save(out, "set", "\n".join(sets[k:k + 3]) + "\n")
    for s in csv_seeds():
        save(out, "csv", s)
    for s in stl_seeds():
        save(out, "stl", s)
    for s in ckpt_seeds(esfera):
        save(out, "ckpt", s)
    with open(os.path.join(out, "yaml.dict"), "w") as f:
        f.write(yaml_dict())
    for name, toks in (("stl", STL_DICT), ("csv", CSV_DICT), ("ckpt", CKPT_DICT)):
        with open(os.path.join(out, name + ".dict"), "w") as f:
            f.write("\n".join(dict_line(t.encode("latin-1")) for t in toks) + "\n")
    for h in ("scene", "set", "csv", "stl", "ckpt"):
        files = os.listdir(os.path.join(out, h))
        size = sum(os.path.getsize(os.path.join(out, h, f)) for f in files)
        print(f"corpus: {h}: {len(files)} seeds, {size} bytes")


if __name__ == "__main__":
    main()
