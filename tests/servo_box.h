/* servo_box.h — the servo-confined packing shared by the sand-production tests
 * (test_servo, test_drag, test_loads_ckpt): 80 spheres of material `m` (radii 3-4 mm)
 * in a 0.04 m square box open at the top, under a servo lid that starts at z = 0.06 m
 * and holds 2e4 Pa (max 0.2 m/s). The scene's name, gravity, materials and the rest
 * come before and after it. */
#ifndef ESF_SERVO_BOX_H
#define ESF_SERVO_BOX_H

#define SERVO_BOX_YAML                                                                   \
  "particles:\n"                                                                         \
  "  - {generate: random, region: {min: [0, 0, 0], max: [0.04, 0.04, 0.05]}, count: "    \
  "80, radius: {uniform: [0.003, 0.004]}, material: m, seed: 11}\n"                      \
  "walls:\n"                                                                             \
  "  - {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.2]}, open: [top], material: m}\n"      \
  "  - polygon: [[0, 0, 0.06], [0.04, 0, 0.06], [0.04, 0.04, 0.06], [0, 0.04, 0.06]]\n"  \
  "    material: m\n"                                                                    \
  "    motion: {servo: {stress: 2.0e4, direction: [0, 0, -1], max_speed: 0.2}}\n"

/* Water through the box toward a drilled hole along y at x = z = 0.02 m (well radius
 * 8 mm, 3e5 Pa drop over a 1 m drainage radius), the `fluid:` keys after start and
 * porosity; then the leapfrog at 0.2 of the critical step. */
#define SERVO_BOX_RADIAL_FLOW                                                            \
  "  viscosity: 1.0e-3\n"                                                                \
  "  density: 1000\n"                                                                    \
  "  permeability: 1.0e-10\n"                                                            \
  "  radial: {center: [0.02, 0.02, 0.02], axis: [0, 1, 0], well_radius: 0.008, "         \
  "drainage_radius: 1, pressure_drop: 3.0e5}\n"                                          \
  "integrator: {method: leapfrog, dt: auto, frac: 0.1}\n"

#endif
