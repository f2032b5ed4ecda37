#!/usr/bin/env bash
# bad_input.sh ESFERA — bad scenes and options get exit status 2 and a message naming
# the place (file:line:column, or the --set override); a numerically failing run gets
# exit status 1 naming the step, the particle, dt and the critical dt. Earlier output
# stays intact.
set -u
esfera=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

good() {  # a valid scene; $1 extra text appended to particles, $2 extra top-level text
  cat <<YAML
name: bad
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {material: glass, radius: 0.005, position: [0, 0, 0.01]}
$1
walls:
  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
run: {steps: 10}
output: {energy_every: 0}
$2
YAML
}

expect() {  # expect NAME STATUS PATTERN -- esfera arguments...
  local name=$1 status=$2 pattern=$3
  shift 4
  local out
  out=$(timeout -k 5 60 "$esfera" "$@" 2>&1 >/dev/null) # a hang fails too
  local rc=$?
  if [ "$rc" = "$status" ] && printf '%s\n' "$out" | grep -Eq -- "$pattern"; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    printf 'FAIL %s: exit %s (want %s), message:\n  %s\n  (want /%s/)\n' "$name" "$rc" \
      "$status" "$out" "$pattern"
  fi
}

good "" "" > "$tmp/ok.yaml"
expect "valid scene runs" 0 "^$" -- run "$tmp/ok.yaml" --out "$tmp/o0" --quiet

good "  - {material: sand, radius: 0.005, position: [0.1, 0, 0.01]}" "" > "$tmp/s1.yaml"
expect "missing material" 2 "s1.yaml:6:[0-9]+: .*unknown material 'sand' \(defined: glass\)" \
  -- run "$tmp/s1.yaml" --out "$tmp/o1"

good "  - {material: glass, radius: -0.005, position: [0.1, 0, 0.01]}" "" > "$tmp/s2.yaml"
expect "negative radius" 2 "s2.yaml:6:[0-9]+: particles.1.radius: must be positive" \
  -- run "$tmp/s2.yaml" --out "$tmp/o2"

sed 's/density: 2500/densty: 2500/' "$tmp/ok.yaml" > "$tmp/s3.yaml"
expect "misspelt key" 2 "s3.yaml:3:[0-9]+: unknown key 'densty' in materials.glass \(did you mean 'density'\?\)" \
  -- run "$tmp/s3.yaml" --out "$tmp/o3"

sed 's/kn: 1.0e5/kn: stiff/' "$tmp/ok.yaml" > "$tmp/s4.yaml"
expect "wrong type" 2 "s4.yaml:3:[0-9]+: materials.glass.kn: expected a number, got 'stiff'" \
  -- run "$tmp/s4.yaml" --out "$tmp/o4"

sed 's/friction: 0.3}/friction: 0.3, rolling_friction: -0.1}/' "$tmp/ok.yaml" > "$tmp/s4r.yaml"
expect "negative rolling friction" 2 "s4r.yaml:3:[0-9]+: materials.glass.rolling_friction: must be non-negative, got -0.1" \
  -- run "$tmp/s4r.yaml" --out "$tmp/o4r"

good "" "contact: {rolling: sticky}" > "$tmp/s4m.yaml"
expect "unknown rolling model" 2 "s4m.yaml:[0-9]+:[0-9]+: .*rolling.*(epsd|cdt)" \
  -- run "$tmp/s4m.yaml" --out "$tmp/o4m"

sed 's/friction: 0.3}/friction: 0.3, rolling_friction: 0.1}/' "$tmp/ok.yaml" > "$tmp/s4h.yaml"
expect "rolling with history as state" 2 "integrator.history=state: .*rolling resistance" \
  -- run "$tmp/s4h.yaml" --out "$tmp/o4h" --set integrator.method=rk4 \
  --set integrator.history=state

good "  - {material: glass, radius: 0.005, position: [0.009, 0, 0.01]}" "" > "$tmp/s5.yaml"
expect "overlapping explicit particles" 2 "s5.yaml:6:[0-9]+: this particle overlaps the one at .*s5.yaml:5:[0-9]+" \
  -- run "$tmp/s5.yaml" --out "$tmp/o5"

good "  - {file: missing.csv, material: glass}" "" > "$tmp/s6.yaml"
expect "unreadable CSV" 2 "s6.yaml:6:[0-9]+: particles from file: cannot open '.*missing.csv'" \
  -- run "$tmp/s6.yaml" --out "$tmp/o6"

printf 'x,y,z,radius\n0.1,0,0.01,abc\n' > "$tmp/bad.csv"
good "  - {file: bad.csv, material: glass}" "" > "$tmp/s7.yaml"
expect "bad CSV value" 2 "bad.csv:2:4: expected a number, got 'abc'" \
  -- run "$tmp/s7.yaml" --out "$tmp/o7"

expect "unknown --set key" 2 "^esfera: --set integrator.fracc=0.2: unknown key 'fracc' in integrator \(did you mean 'frac'\?\)" \
  -- run "$tmp/ok.yaml" --set integrator.fracc=0.2 --out "$tmp/o8"

expect "--set wrong type" 2 "--set gravity=\[0,0\]: gravity: expected a sequence of 3 numbers, got 2 items" \
  -- run "$tmp/ok.yaml" --set 'gravity=[0,0]' --out "$tmp/o9"

# walls.csv and stress.csv (output.walls, output.stress) need energy rows; regions
# are boxes with min < max
expect "output.walls without energy rows" 2 "--set output.walls=true: output.walls: written at the energy rows: needs output.energy_every > 0" \
  -- run "$tmp/ok.yaml" --set output.walls=true --out "$tmp/o9w"
expect "stress region min > max" 2 "output.stress.0.region: min must be below max in every direction" \
  -- run "$tmp/ok.yaml" --set output.energy_every=1e-4 \
  --set 'output.stress=[{region: {min: [0,0,1], max: [1,1,0]}}]' --out "$tmp/o9s"
expect "stress entry without region" 2 "unknown key 'box' in output.stress.0 \(expected one of: region\)" \
  -- run "$tmp/ok.yaml" --set output.energy_every=1e-4 --set 'output.stress=[{box: 1}]' \
  --out "$tmp/o9t"

good "" "integrator: {dt: 1.0}" > "$tmp/s10.yaml"
expect "dt above critical" 2 "above the critical step of the 'hart' rule" \
  -- run "$tmp/s10.yaml" --out "$tmp/o10"

printf 'name: x\nmaterials: {a: {kn: 1}\nparticles: []\n' > "$tmp/s11.yaml"
expect "YAML syntax" 2 "s11.yaml:[0-9]+:[0-9]+: YAML syntax error" -- run "$tmp/s11.yaml"

expect "missing scene file" 2 "nothere.yaml.*(cannot open|No such file)" -- run "$tmp/nothere.yaml"

good "" "integrator: {method: rk99}" > "$tmp/s13.yaml"
expect "unknown integrator" 2 "s13.yaml:11:[0-9]+: integrator.method: unknown method 'rk99' \(available: leapfrog" -- run "$tmp/s13.yaml"

expect "unknown option" 2 "unknown or incomplete option '--frobnicate'" -- run "$tmp/ok.yaml" --frobnicate

good "" "dimension: 4" > "$tmp/s15.yaml"
expect "bad dimension" 2 "s15.yaml:11:[0-9]+: dimension: must be 2 or 3, got 4" -- run "$tmp/s15.yaml"
expect "history as state with the leapfrog" 2 "integrator.history: state .* erk: methods only, not leapfrog" \
  -- run "$tmp/ok.yaml" --out "$tmp/o17" --set integrator.history=state
expect "roots without an adaptive erk" 2 "integrator.roots: .*adaptive erk: methods only \(rtol > 0\), not rk4" \
  -- run "$tmp/ok.yaml" --out "$tmp/o18" --set integrator.roots=true --set integrator.method=rk4

# bond: the adhesive law's parameters (docs/physics.md#adhesive-normal-law-and-bonds):
# epsilon in (0, 1) but not 1/e, F >= 0, and a skin that keeps bonds in tension as
# candidates
sed 's/friction: 0.3}/friction: 0.3, adhesion: {force: 1, epsilon: 0.36787944117144233}}/' \
  "$tmp/ok.yaml" > "$tmp/b1.yaml"
expect "adhesion epsilon 1/e" 2 "b1.yaml:3:[0-9]+: materials.glass.adhesion.epsilon: .*1/e" \
  -- run "$tmp/b1.yaml" --out "$tmp/ob1"
sed 's/friction: 0.3}/friction: 0.3, adhesion: {force: 1, epsilon: 1.0}}/' \
  "$tmp/ok.yaml" > "$tmp/b2.yaml"
expect "adhesion epsilon 1" 2 "b2.yaml:3:[0-9]+: materials.glass.adhesion.epsilon: epsilon must lie in \(0, 1\)" \
  -- run "$tmp/b2.yaml" --out "$tmp/ob2"
sed 's/friction: 0.3}/friction: 0.3, adhesion: {force: -2, epsilon: 0.5}}/' \
  "$tmp/ok.yaml" > "$tmp/b3.yaml"
expect "adhesion negative force" 2 "b3.yaml:3:[0-9]+: materials.glass.adhesion.force: must be a non-negative force" \
  -- run "$tmp/b3.yaml" --out "$tmp/ob3"
sed 's/friction: 0.3}/friction: 0.3, adhesion: {force: 1, epsilon: 0.5, bond_gap: 0.01}}/' \
  "$tmp/ok.yaml" > "$tmp/b4.yaml"
expect "skin below the bond reach" 2 "search.skin = 0.001 m does not exceed the bond reach" \
  -- run "$tmp/b4.yaml" --out "$tmp/ob4" --set search.skin=0.001
sed 's/friction: 0.3}/friction: 0.3, adhesion: {force: 1, epsilon: 0.5, bond_gp: 0}}/' \
  "$tmp/ok.yaml" > "$tmp/b5.yaml"
expect "adhesion misspelt key" 2 "b5.yaml:3:[0-9]+: unknown key 'bond_gp'" \
  -- run "$tmp/b5.yaml" --out "$tmp/ob5"

# numerical failure: exit 1, with the step, particle, dt and critical dt; frames so far kept
cat > "$tmp/s16.yaml" <<'YAML'
name: column
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.9, friction: 0.3}
particles:
  - {generate: lattice, region: {min: [0, 0, 0], max: [0.01, 0.01, 0.1]}, radius: 0.005,
     material: glass}
walls:
  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
integrator: {dt: 4.0e-4, allow_unstable: true}
run: {steps: 2000}
output: {energy_every: 1.0e-4}
YAML
expect "unstable run stops" 1 "step [0-9]+ .*particles? id [0-9]+.*dt = 0.0004 s, critical dt \(hart\) = .* s" \
  -- run "$tmp/s16.yaml" --out "$tmp/o16"
if [ -s "$tmp/o16/frames.h5" ] && grep -q "FAILED" "$tmp/o16/log.txt"; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL failed run keeps frames.h5 and logs the failure"
fi

# mesh walls (STL files, generators): errors name the scene key and the file's line or
# triangle; exit 2
printf 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 2 2 0\nendloop\nendfacet\nendsolid\n' > "$tmp/flat.stl"
good "" "" | sed 's|  - {plane: {point: \[0, 0, 0\], normal: \[0, 0, 1\]}, material: glass}|  - {mesh: {file: flat.stl, scale: 0.1}, material: glass}|' > "$tmp/m1.yaml"
expect "degenerate STL triangle" 2 "m1.yaml:8:[0-9]+: wall mesh: .*flat.stl:9: ASCII STL facet 2: degenerate triangle \(zero or near-zero area" \
  -- run "$tmp/m1.yaml" --out "$tmp/om1"
head -c 150 /dev/zero > "$tmp/trunc.stl"
sed 's/flat.stl/trunc.stl/' "$tmp/m1.yaml" > "$tmp/m2.yaml"
expect "truncated binary STL" 2 "m2.yaml:8:[0-9]+: wall mesh: .*trunc.stl: binary STL of 150 bytes, but its header announces 0 triangles = 84 bytes" \
  -- run "$tmp/m2.yaml" --out "$tmp/om2"
sed 's/flat.stl/none.stl/' "$tmp/m1.yaml" > "$tmp/m3.yaml"
expect "missing STL file" 2 "m3.yaml:8:[0-9]+: wall mesh: .*none.stl: cannot open STL file" \
  -- run "$tmp/m3.yaml" --out "$tmp/om3"
good "" "" | sed 's|  - {plane: {point: \[0, 0, 0\], normal: \[0, 0, 1\]}, material: glass}|  - {screw: {base: [0, 0, 0], shaft_radius: 0.02, radius: 0.01, pitch: 0.1, turns: 2}, material: glass}|' > "$tmp/m4.yaml"
expect "screw thinner than its shaft" 2 "m4.yaml:8:[0-9]+: walls.0.screw: a screw needs 0 < shaft_radius \(0.02 m\) < radius \(0.01 m\)" \
  -- run "$tmp/m4.yaml" --out "$tmp/om4"
sed 's/pitch: 0.1/pich: 0.1/' "$tmp/m4.yaml" > "$tmp/m5.yaml"
expect "misspelt screw key" 2 "m5.yaml:8:[0-9]+: unknown key 'pich' in walls.0.screw \(did you mean 'pitch'\?\)" \
  -- run "$tmp/m5.yaml" --out "$tmp/om5"

# sand production keys (servo walls, events, fluid)
good "" "events: [{at: 0.1, delete: {cylinder: {center: [0, 0, 0], axis: [0, 1, 0], radius: 0.1}, box: {min: [0, 0, 0], max: [1, 1, 1]}}}]" > "$tmp/s30.yaml"
expect "event with two regions" 2 "s30.yaml:11:[0-9]+: .*exactly one region" \
  -- run "$tmp/s30.yaml" --out "$tmp/o30"
good "" "fluid: {porosity: 0.4, viscosity: 1.0e-3, density: 1000, uniform: {velocty: [0, 0, 1]}}" > "$tmp/s31.yaml"
expect "misspelt fluid key" 2 "s31.yaml:11:[0-9]+: unknown key 'velocty'" \
  -- run "$tmp/s31.yaml" --out "$tmp/o31"
good "" "fluid: {porosity: 0.4, viscosity: 1.0e-3, density: 1000}" > "$tmp/s32.yaml"
expect "fluid without a field" 2 "s32.yaml:11:[0-9]+: .*exactly one fluid field" \
  -- run "$tmp/s32.yaml" --out "$tmp/o32"
sed 's|normal: \[0, 0, 1\]}, material: glass}|normal: [0, 0, 1]}, material: glass, motion: {servo: {stress: 1.0e4, direction: [0, 0, 1]}}}|' "$tmp/ok.yaml" > "$tmp/s33.yaml"
expect "servo without max_speed" 2 "s33.yaml:8:[0-9]+: .*max_speed" \
  -- run "$tmp/s33.yaml" --out "$tmp/o33"
sed 's|normal: \[0, 0, 1\]}, material: glass}|normal: [0, 0, 1]}, material: glass, motion: {servo: {stress: 1.0e4, direction: [0, 0, 1], max_speed: 1}}}|' "$tmp/ok.yaml" > "$tmp/s34.yaml"
expect "servo plane without area" 2 "servo wall 'plane 0': give motion.servo.area" \
  -- run "$tmp/s34.yaml" --out "$tmp/o34"
expect "servo refused by an ODE method" 2 "servo walls are supported by the leapfrog only" \
  -- run "$tmp/s34.yaml" --out "$tmp/o35" --set walls.0.motion.servo.area=1 --set integrator.method=rk4

good "" "events: [{at: 0.0, delete: {box: {min: [-1, -1, -1], max: [1, 1, 1]}}}]" > "$tmp/s36.yaml"
expect "events refused by an ODE method" 2 "events \(deleting particles, removing or adding walls\) are supported by the leapfrog only" \
  -- run "$tmp/s36.yaml" --out "$tmp/o36" --set integrator.method=verlet

sed 's|- {plane: {point: \[0, 0, 0\], normal: \[0, 0, 1\]}, material: glass}|- {box: {min: [-1, -1, 0], max: [1, 1, 1]}, material: glass, motion: {servo: {stress: 1, direction: [0, 0, 1], max_speed: 1}}}|' "$tmp/ok.yaml" > "$tmp/s37.yaml"
expect "servo box refused" 2 "s37.yaml:8:[0-9]+: .*make the servo-controlled face a polygon" \
  -- run "$tmp/s37.yaml" --out "$tmp/o37"

# issue 27: every exit-2 message names its place; no message of a library before
# esfera's own; --out and the output folder
only() {  # only NAME STATUS PATTERN -- args: the whole of stderr is one line matching
  local name=$1 status=$2 pattern=$3
  shift 4
  local out rc
  out=$(timeout -k 5 60 "$esfera" "$@" 2>&1 >/dev/null) # a hang fails too
  rc=$?
  if [ "$rc" = "$status" ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] &&
    printf '%s\n' "$out" | grep -Eq -- "$pattern"; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    printf 'FAIL %s: exit %s (want %s), message (want one line /%s/):\n%s\n' "$name" \
      "$rc" "$status" "$pattern" "$out"
  fi
}
good "" "integrator: {dt: 1.0e-300}" | sed 's/run: {steps: 10}/run: {duration: 0.01}/' \
  > "$tmp/s40.yaml"
only "dt too small for the duration" 2 "^esfera: .*s40.yaml:9:[0-9]+: run.duration = 0.01 s at dt = 1e-300 s is 1e\+298 steps" \
  -- run "$tmp/s40.yaml" --out "$tmp/o40"
[ -e "$tmp/o40" ] && { fail=$((fail + 1)); echo "FAIL a refused step count wrote output"; }
only "too many steps" 2 "^esfera: --set run.steps=2000000000000: run.steps: 2000000000000 steps is more than" \
  -- run "$tmp/ok.yaml" --out "$tmp/o41" --set run.steps=2000000000000
sed 's/density: 2500, //' "$tmp/ok.yaml" > "$tmp/s42.yaml"
only "no density" 2 "^esfera: .*s42.yaml:3:[0-9]+: materials.glass: material 'glass' is used by particle id 0 and needs a positive density" \
  -- run "$tmp/s42.yaml" --out "$tmp/o42"
only "density 0" 2 "^esfera: --set materials.glass.density=0: materials.glass.density: .*needs a positive density" \
  -- run "$tmp/ok.yaml" --out "$tmp/o43" --set materials.glass.density=0
only "step rounded to 0" 2 "^esfera: --set integrator.frac=1e-320: integrator.frac: the time step must be a positive .* got 0 s" \
  -- run "$tmp/ok.yaml" --out "$tmp/o44" --set integrator.frac=1e-320
good "" "integrator: {method: \"erk:NOPE\"}" > "$tmp/s45.yaml"
only "unknown ERK table, esfera's message alone" 2 "^esfera: .*s45.yaml:11:[0-9]+: integrator.method: 'erk:NOPE' is not an explicit Runge-Kutta table" \
  -- run "$tmp/s45.yaml" --out "$tmp/o45"
[ -e "$tmp/o45" ] && { fail=$((fail + 1)); echo "FAIL a scheme refused at set-up wrote output"; }
only "unknown method, located" 2 "^esfera: .*s13.yaml:11:[0-9]+: integrator.method: unknown method" \
  -- run "$tmp/s13.yaml" --out "$tmp/o46"
only "dt above critical, located" 2 "^esfera: .*s10.yaml:11:[0-9]+: integrator.dt = 1 s is above" \
  -- run "$tmp/s10.yaml" --out "$tmp/o47"
only "checkpoints by a method without them, located" 2 "^esfera: --set output.checkpoint_every=0.1: output.checkpoint_every: integrator cvode-adams cannot" \
  -- run "$tmp/ok.yaml" --out "$tmp/o48" --set integrator.method=cvode-adams --checkpoint-every 0.1
: > "$tmp/plain"
only "--out names a regular file" 2 "^esfera: .*plain' is not a directory" \
  -- run "$tmp/ok.yaml" --out "$tmp/plain"
only "rerun into a folder with results" 2 "^esfera: the output folder '.*o0' holds another run's results \(frames.h5.*log.txt\): give --overwrite" \
  -- run "$tmp/ok.yaml" --out "$tmp/o0" --quiet
expect "rerun with --overwrite" 0 "^$" -- run "$tmp/ok.yaml" --out "$tmp/o0" --quiet --overwrite
expect "--overwrite with --resume" 2 "--resume DIR continues a run" -- run --resume "$tmp/o0" --overwrite

# initial overlaps are bad input with their own message (not the first step's failure)
good "  - {material: glass, radius: 0.005, position: [0.1, 0, 0.003]}" "" > "$tmp/s50.yaml"
only "sphere pressed into a wall" 2 "^esfera: .*s50.yaml:6:[0-9]+ \(particles.1\): particle id 1 at \(0.1, 0, 0.003\) m, radius 0.005 m, starts overlapping wall element 0 of walls.0 \('plane 0' at .*s50.yaml:8:[0-9]+\) by 0.002 m, 40% of its radius .*allow_initial_overlap" \
  -- run "$tmp/s50.yaml" --out "$tmp/o50"
expect "pressed in, allowed" 0 "^$" -- run "$tmp/s50.yaml" --out "$tmp/o51" --quiet \
  --set contact.allow_initial_overlap=true
only "deep in a wall, allowed or not" 2 "^esfera: .*particle id 1 .* by 0.004 m, 80% of its radius \(limit 50%\), more than contact.max_overlap allows" \
  -- run "$tmp/s50.yaml" --out "$tmp/o52" --set contact.allow_initial_overlap=true \
  --set 'particles.1.position=[0.1,0,0.001]'
printf 'x,y,z,radius\n0.3,0,0.001,0.005\n0.5,0,0.01,0.005\n0.7,0,0.01,0.005\n' > "$tmp/deep.csv"
good "  - {file: deep.csv, material: glass}" "" > "$tmp/s53.yaml"
only "a packing's sphere deep in a wall" 2 "^esfera: .*s53.yaml:6:[0-9]+ \(particles.1, a row of its file\): particle id 1 .* by 0.004 m, 80%" \
  -- run "$tmp/s53.yaml" --out "$tmp/o53"
printf 'x,y,z,radius\n0.3,0,0.01,0.005\n0.5,0,0.01,0.005\n0.5,0,0.012,0.005\n' > "$tmp/deep2.csv"
sed 's/deep.csv/deep2.csv/' "$tmp/s53.yaml" > "$tmp/s54.yaml"
only "two packed spheres deep in each other" 2 "^esfera: .*s54.yaml:6:[0-9]+ \(particles.1, a row of its file\): particle id 2 and particle id 3 .* start overlapping by 0.008 m, 160% of the smaller radius" \
  -- run "$tmp/s54.yaml" --out "$tmp/o54"

# the Hertz-Mindlin law (docs/scene.md#materials): kn and youngs_modulus together, a
# Hertz material meeting a linear one, adhesion with Hertz, a bad poisson_ratio
sed 's/kn: 1.0e5,/kn: 1.0e5, youngs_modulus: 1e9, poisson_ratio: 0.3,/' "$tmp/ok.yaml" > "$tmp/h1.yaml"
expect "kn and youngs_modulus together" 2 "h1.yaml:3:[0-9]+: .*give kn \(the linear law\) or youngs_modulus and poisson_ratio" \
  -- run "$tmp/h1.yaml" --out "$tmp/oh1"
sed 's/^  glass: .*/  glass: {density: 2500, youngs_modulus: 1e9, poisson_ratio: 0.3}\n  steel: {density: 7800, kn: 1.0e5}/' \
  "$tmp/ok.yaml" > "$tmp/h2.yaml"
expect "Hertz meets linear" 2 "h2.yaml:4:[0-9]+: .*material 'steel' uses the linear law, material 'glass' the Hertz-Mindlin law" \
  -- run "$tmp/h2.yaml" --out "$tmp/oh2"
sed 's/kn: 1.0e5,/youngs_modulus: 1e9, poisson_ratio: 0.3, adhesion: {force: 1, epsilon: 0.5},/' \
  "$tmp/ok.yaml" > "$tmp/h3.yaml"
expect "adhesion with Hertz" 2 "h3.yaml:3:[0-9]+: .*adhesion .*not defined for a Hertz-Mindlin material" \
  -- run "$tmp/h3.yaml" --out "$tmp/oh3"
sed 's/kn: 1.0e5,/youngs_modulus: 1e9, poisson_ratio: 0.5,/' "$tmp/ok.yaml" > "$tmp/h4.yaml"
expect "poisson_ratio 0.5" 2 "h4.yaml:3:[0-9]+: materials.glass.poisson_ratio: must be in \[0, 0.5\)" \
  -- run "$tmp/h4.yaml" --out "$tmp/oh4"
sed 's/kn: 1.0e5,/youngs_modulus: 1e9,/' "$tmp/ok.yaml" > "$tmp/h5.yaml"
expect "youngs_modulus without poisson_ratio" 2 "h5.yaml:3:[0-9]+: .*needs both youngs_modulus and poisson_ratio" \
  -- run "$tmp/h5.yaml" --out "$tmp/oh5"

sed 's/kn: 1.0e5,/youngs_modulus: 1e9, poisson_ratio: 0.3,/; s|normal: \[0, 0, 1\]}, material: glass}|normal: [0, 0, 1]}, material: glass, motion: {servo: {stress: 1.0e4, direction: [0, 0, 1], max_speed: 0.1, area: 0.01}}}|' \
  "$tmp/ok.yaml" > "$tmp/h7.yaml"
expect "servo walls with Hertz" 2 "h7.yaml:[0-9]+:[0-9]+: servo walls need the linear law's kn" \
  -- run "$tmp/h7.yaml" --out "$tmp/oh7"
expect "Hertz in 2D" 2 "h5.yaml:[0-9]+:[0-9]+: the Hertz-Mindlin law .* is the law of spheres" \
  -- run "$tmp/h5.yaml" --set 'materials.glass.poisson_ratio=0.3' --set dimension=2 --out "$tmp/oh8"
expect "rayleigh rule with the linear law" 2 "--set integrator.dt_rule=rayleigh: integrator.dt_rule: rayleigh needs the Hertz-Mindlin law" \
  -- run "$tmp/ok.yaml" --set integrator.dt_rule=rayleigh --out "$tmp/oh6"

# Butcher tables from the scene (integrator.table): each check fails at its node
table() {  # $1: c, $2: A, $3: b, $4: order, $5 extra table lines
  good "" "integrator:
  method: erk
  table:
    c: $1
    A: $2
    b: $3
    order: $4${5:-}"
}
table "[0, 1/2, 3/4]" "[[], [1/2], [0, 3/4]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t0.yaml"
expect "Ralston 3 typed in runs" 0 "^$" -- run "$tmp/t0.yaml" --out "$tmp/ot0" --quiet
table "[0, 1/2, 3/4]" "[[], [1/2], [0, 3/4, 0.1]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t1.yaml"
expect "table not explicit" 2 "t1.yaml:15:29: integrator.table.A.2.2: a_22 = 0.1: an explicit table has a_ij = 0 for j >= i" \
  -- run "$tmp/t1.yaml" --out "$tmp/ot1"
table "[0, 1/2, 0.7]" "[[], [1/2], [0, 3/4]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t2.yaml"
expect "table c not the row sums" 2 "t2.yaml:14:17: integrator.table.c.2: c_2 = 0.6999.*, but row 2 of A sums to 0.75" \
  -- run "$tmp/t2.yaml" --out "$tmp/ot2"
table "[0, 1]" "[[], [1]]" "[1/2, 1/2]" 3 > "$tmp/t3.yaml"
expect "order 3 claimed for Heun's second-order table" 2 "t3.yaml:17:12: integrator.table.order: order 3 claimed, but b has order 2: the order-3 condition sum b c\^2 = 1/3 fails \(0.5, off by 0.167\)" \
  -- run "$tmp/t3.yaml" --out "$tmp/ot3"
table "[0, 1/2, 3/4]" "[[], [1/2], [0, 3/4]]" "[2/9, 1/3]" 3 > "$tmp/t4.yaml"
expect "table b too short" 2 "t4.yaml:16:8: integrator.table.b: has 2 entries, c has 3 \(one per stage\)" \
  -- run "$tmp/t4.yaml" --out "$tmp/ot4"
table "[0, 1/2, 3/4]" "[[], [1/2]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t5.yaml"
expect "table A short of a row" 2 "t5.yaml:15:8: integrator.table.A: has 2 rows, c has 3 stages" \
  -- run "$tmp/t5.yaml" --out "$tmp/ot5"
table "[0, 1/2, 3/4]" "[[], [1/2, 0, 0, 0], [0, 3/4]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t6.yaml"
expect "table A row of 4 in 3 stages" 2 "t6.yaml:15:13: integrator.table.A.1: row 1 has 4 entries: give 1 .*, 2 .* or 3" \
  -- run "$tmp/t6.yaml" --out "$tmp/ot6"
expect "adaptive steps without an embedding" 2 "^esfera: --set integrator.rtol=1e-6: integrator.rtol: adaptive steps \(rtol > 0\) need an error estimate" \
  -- run "$tmp/t0.yaml" --out "$tmp/ot7" --set integrator.rtol=1e-6
table "[0, 1/2, 3/4]" "[[], [1/2], [0, 3/4]]" "[2/9, 1/3, 4/9]" 3 "
    b_embedded: [0, 1, 0]
    embedded_order: 3" > "$tmp/t8.yaml"
expect "embedded order over-claimed" 2 "t8.yaml:19:21: integrator.table.embedded_order: order 3 claimed, but b_embedded has order 2: the order-3 condition sum b_embedded c\^2 = 1/3 fails \(0.25, off by -0.0833\)" \
  -- run "$tmp/t8.yaml" --out "$tmp/ot8"
expect "a table for another method" 2 "t0.yaml:14:5: integrator.table: a Butcher table is for method: erk \(method is rk4\)" \
  -- run "$tmp/t0.yaml" --out "$tmp/ot9" --set integrator.method=rk4
good "" "integrator: {method: erk}" > "$tmp/t10.yaml"
expect "method erk without a table" 2 "t10.yaml:11:22: integrator.method: method erk takes its Butcher table from integrator.table" \
  -- run "$tmp/t10.yaml" --out "$tmp/ot10"
table "[0, 1/2, 3/4]" "[[], [1/0], [0, 3/4]]" "[2/9, 1/3, 4/9]" 3 > "$tmp/t11.yaml"
expect "table entry 1/0" 2 "t11.yaml:15:14: integrator.table.A.1.0: expected a number or a fraction p/q, got '1/0'" \
  -- run "$tmp/t11.yaml" --out "$tmp/ot11"
table "[0, 1/2, 3/4]" "[[], [1/2], [0, 3/4]]" "[2/9, 1/3, 4/9]" 9 > "$tmp/t12.yaml"
expect "order beyond the checked ones" 2 "t12.yaml:17:12: integrator.table.order: must be 1 to 8" \
  -- run "$tmp/t12.yaml" --out "$tmp/ot12"

echo "bad_input: $pass passed, $fail failed"
[ "$fail" = 0 ]
