"""chung_ooi_published.py -- the published curves of Chung & Ooi (2011), tests 4, 5 and 7,
as digitised points (x, y), and where they come from.

Chung Y.C., Ooi J.Y., "Benchmark tests for verifying discrete element modelling codes at
particle impact level", Granular Matter 13 (2011) 643-656, doi:10.1007/s10035-011-0277-0.

The paper's figures were not available here as text or data. The points below were
digitised from its figures by a third party and published as CSV files in the PySPH fork
github.com/dineshadepu/pysph, directory pysph/examples/dem/discontinuous_dem/ (commits
named per set). Which curve of each figure was digitised is not recorded there;
judging from the values (they meet the gross-sliding closed forms at large angles) they
are the figures' reference curves. Digitising error: about 1 % of each axis range.
Signs: the angular velocities are as printed in the paper (negative: the spin that a
forward-sliding sphere acquires); chung_ooi.py compares magnitudes with the same sign
convention.

Where the fork holds two differently scaled versions of one set (test 4 tangential
restitution: minima 0.37 and 0.61), the one that meets the closed form of gross sliding
e_t = 1 - mu (1 + e) / tan(theta) at large angles is kept (minimum 0.61); the other
matches no definition of e_t we know of.
"""

SOURCE = ("Chung & Ooi (2011) figures, digitised by a third party: CSV files of "
          "github.com/dineshadepu/pysph, pysph/examples/dem/discontinuous_dem/")

# Test 4 (3.9 m/s at angles 5-85 deg, e = 0.98, mu = 0.092, R = 2.5 mm).
# Tangential restitution e_t = v_t'/v_t at the centre of mass against the angle (deg).
# chung_test_4_incident_angle_vs_tng_restitution_al_oxide.csv (commit 947c241)
T4_ET_AL_OXIDE = [
    (5.111, 0.9492), (9.833, 0.6876), (14.95, 0.6244), (19.93, 0.6145), (25.01, 0.6355),
    (29.49, 0.6802), (35.16, 0.7372), (39.76, 0.7806), (49.80, 0.8438), (59.84, 0.8909),
    (69.89, 0.9331), (79.71, 0.9702), (84.79, 0.9864)]
# test_chung_paper/chung_test_4_incident_angle_vs_tng_restitution_al_alloy.csv (8250c36)
T4_ET_AL_ALLOY = [
    (4.776, 0.8983), (9.839, 0.6715), (15.19, 0.6107), (19.93, 0.6058), (24.66, 0.6343),
    (29.49, 0.6777), (34.56, 0.7360), (39.99, 0.7818), (49.56, 0.8463), (59.73, 0.8909),
    (69.42, 0.9318), (79.95, 0.9665), (84.44, 0.9826)]
# Angular velocity after the impact (rad/s) against the angle (deg), aluminium oxide.
# chung_test_4_incident_angle_vs_post_collision_angular_velocity.csv (372f2ab)
T4_OMEGA_AL_OXIDE = [
    (4.771, -21.01), (9.725, -211.1), (14.80, -373.3), (19.86, -505.8), (25.04, -593.1),
    (29.81, -608.9), (34.82, -582.8), (39.70, -541.1), (49.59, -461.1), (59.73, -358.5),
    (69.48, -245.4), (79.61, -121.8), (84.61, -66.13)]

# Test 5 (v_n = 5 m/s, v_t 0.1-21 m/s, e = 1, mu = 0.3, R = 10 um): against the normalised
# incident angle Psi_in = v_t/(mu v_n), the normalised recoil angle
# Psi_out = v_c'/(mu v_n') (v_c' the contact point's tangential velocity after) and the
# normalised spin R w'/(mu v_n).
# chung_test_5_normalized_recoil_angle_vs_normalized_incident_angle_steel.csv (372f2ab)
T5_RECOIL_STEEL = [
    (0.04929, -0.1088), (0.2386, -0.2971), (0.6736, -0.5481), (0.9763, -0.7364),
    (1.336, -1.008), (1.676, -1.301), (2.036, -1.552), (2.339, -1.866), (3.001, -2.452),
    (3.342, -2.640), (4.003, -2.745), (5.003, -1.992), (6.002, -1.029), (10.00, 2.946),
    (12.30, 5.435)]
# test_chung_paper/..._recoil_angle_..._polyethylene.csv (8250c36)
T5_RECOIL_PE = [
    (0.04917, -0.04603), (0.3331, -0.3389), (0.6736, -0.5272), (1.014, -0.9038),
    (1.336, -1.113), (1.677, -1.490), (1.980, -1.782), (2.339, -2.096), (2.964, -2.724),
    (3.342, -2.954), (4.022, -2.891), (5.041, -2.033), (5.965, -1.050), (10.00, 2.967),
    (12.32, 5.331)]
# chung_test_5_normalized_post_collision_ang_vel_..._steel.csv (07c488e)
T5_SPIN_STEEL = [
    (0.05659, -0.1330), (0.3698, -0.4521), (0.7685, -0.8509), (1.024, -1.276),
    (1.365, -1.662), (1.735, -2.101), (2.019, -2.526), (2.361, -2.978), (3.014, -3.896),
    (3.327, -4.282), (4.068, -4.840), (4.983, -4.986), (5.956, -4.985), (9.962, -4.956),
    (17.46, -4.951), (20.01, -4.949)]
# test_chung_paper/..._post_collision_ang_vel_..._polyethylene.csv (8250c36)
T5_SPIN_PE = [
    (0.1138, -0.1463), (0.2840, -0.4522), (0.6252, -0.9043), (0.9665, -1.330),
    (1.279, -1.795), (1.678, -2.207), (2.019, -2.673), (2.331, -3.112), (3.042, -4.069),
    (3.269, -4.495), (3.954, -4.920), (4.983, -4.986), (5.956, -4.985), (9.962, -4.956),
    (17.46, -4.951), (20.01, -4.949)]

# Test 7 (two identical spheres, +-0.2 m/s, spins +-w0, 0.175-21 rad/s, e = 0.5,
# mu = 0.4, R = 0.1 m), copper: tangential velocity of the centre of mass after the
# impact (m/s) against w0 (rad/s); zero within the digitising error.
# chung_test_7_pre_c_ang_vel_vs_post_c_tng_vel_copper.csv (3f035b8)
T7_VT_COPPER = [
    (-0.0331, 0.02096), (0.1325, 0.02096), (0.2649, 0.02096), (1.060, -0.02096),
    (1.589, 0.02096), (2.517, -0.02096), (4.238, 0.02096), (5.430, -0.06289),
    (7.483, -0.1048), (11.19, -0.1048), (22.85, 0.02096)]
