/* law_body.h — the contact formulas written once, over a lane type: the pair's geometry
 * and contact velocity, the linear normal law, the tangential force every law shares,
 * and the forces and torques. Included (no guard: once per lane type) by a file that
 * first defines
 *   LANE_R          the lane: double, or a vector of doubles (GCC vector extension)
 *   LANE_M          a mask of lanes: what LANE_R's comparisons give (int, or a vector)
 *   LANE_SEL(m,a,b) per lane, m ? a : b
 *   LANE_SQRT(x)    per lane, sqrt
 *   LANE_ANY(m)     whether some lane of m is set
 *   LANE_POW(x, y)  per lane, pow(x, y) for a double y
 *   LANE_FN(name)   the name of this lane type's copy of a function
 *   LANE_INLINE     how its functions are declared (static inline; the batches force
 *                   inlining, so that a batch's law is one body)
 * (contact/lane_scalar.h: double, for the general path and the ODE methods;
 * fused/pair_batch.c: eight lanes for the fused step's batches). Every copy performs the
 * same IEEE operations in the same order per lane, so a pair's result does not depend
 * on which copy computed it, bit for bit (test contact_lanes).
 * Physics: docs/physics.md#contact-kinematics, #linear-springdashpot-law,
 * #tangential-force-and-the-mohr-coulomb-cap (000 3-15..3-26, 004 2.9-2.16, 2.28).
 * Conventions: n from A to B, un > 0 overlapping, vc = B's contact point minus A's,
 * forces on A. Units: SI. */

LANE_INLINE LANE_R LANE_FN(esf_law_dot)(const LANE_R a[3], const LANE_R b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

LANE_INLINE void LANE_FN(esf_law_cross)(LANE_R r[3], const LANE_R a[3],
                                        const LANE_R b[3]) {
  const LANE_R x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
               z = a[0] * b[1] - a[1] * b[0];
  r[0] = x;
  r[1] = y;
  r[2] = z;
}

/* A pair's separation d = xB - xA and whether the spheres overlap,
 * |d|^2 < (rA + rB)^2 (the one overlap test of every path: the fused step screens its
 * candidates with the same operations). */
LANE_INLINE LANE_M LANE_FN(esf_law_pair_overlap)(const LANE_R xa[3], const LANE_R xb[3],
                                                 LANE_R ra, LANE_R rb, LANE_R d[3],
                                                 LANE_R *d2) {
  for (int q = 0; q < 3; q++) d[q] = xb[q] - xa[q];
  *d2 = LANE_FN(esf_law_dot)(d, d);
  const LANE_R rr = ra + rb;
  return *d2 < rr * rr;
}

/* The relative velocity of a pair's contact point, B's minus A's, for lever arms la,
 * lb along n: vc = (vB - vA) - (la wA + lb wB) x n (000 3-21). */
LANE_INLINE void LANE_FN(esf_law_pair_velocity)(const LANE_R va[3], const LANE_R vb[3],
                                                const LANE_R wa[3], const LANE_R wb[3],
                                                LANE_R la, LANE_R lb, const LANE_R n[3],
                                                LANE_R vc[3]) {
  LANE_R sw[3], c[3];
  for (int q = 0; q < 3; q++) sw[q] = la * wa[q] + lb * wb[q];
  LANE_FN(esf_law_cross)(c, sw, n);
  for (int q = 0; q < 3; q++) vc[q] = vb[q] - va[q] - c[q];
}

/* The rest of a pair's geometry (000 3-15, 3-16, 3-21): n = d/|d| (+z for coincident
 * centres), the overlap un = rA + rB - |d|, the lever arms to the contact point
 * lA = rA - un/2, lB = rB - un/2 (so the tangential forces act at one point), and the
 * contact point's relative velocity (esf_law_pair_velocity). */
LANE_INLINE void LANE_FN(esf_law_pair_kinematics)(const LANE_R d[3], LANE_R d2, LANE_R ra,
                                                  LANE_R rb, const LANE_R va[3],
                                                  const LANE_R vb[3], const LANE_R wa[3],
                                                  const LANE_R wb[3], LANE_R n[3],
                                                  LANE_R *un, LANE_R *la, LANE_R *lb,
                                                  LANE_R vc[3]) {
  const LANE_R zero = {0}, one = zero + 1.0;
  const LANE_R dist = LANE_SQRT(d2);
  const LANE_M pos = dist > 0;
  const LANE_R inv = 1.0 / dist;
  n[0] = LANE_SEL(pos, d[0] * inv, zero);
  n[1] = LANE_SEL(pos, d[1] * inv, zero);
  n[2] = LANE_SEL(pos, d[2] * inv, one);
  *un = (ra + rb) - dist;
  *la = ra - 0.5 * *un;
  *lb = rb - 0.5 * *un;
  LANE_FN(esf_law_pair_velocity)(va, vb, wa, wb, *la, *lb, n, vc);
}

/* The linear normal force (004 2.9-2.12): elastic kn un and dashpot -cn vn (vn < 0
 * approaching), no tension: a negative total is cut to zero, the dashpot's share then
 * -kn un. Returns fn (> 0 compressive); *fd the dashpot's share actually applied. */
LANE_INLINE LANE_R LANE_FN(esf_law_linear_normal)(LANE_R kn, LANE_R cn, LANE_R un,
                                                  LANE_R vn, LANE_R *fd) {
  const LANE_R zero = {0};
  const LANE_R fel = kn * un, fdv = -cn * vn, fn = fel + fdv;
  const LANE_M neg = fn < 0.0;
  *fd = LANE_SEL(neg, -fel, fdv);
  return LANE_SEL(neg, zero, fn);
}

/* The Hertz-Mindlin springs at overlap un > 0 (docs/physics.md#hertz-mindlin-law; Hertz
 * 1882, Mindlin 1949 via Johnson 1985 ch. 4, 7): the contact radius a = sqrt(R* un);
 * with hn = (4/3) E* and ht = 8 G* of the pair, the secant stiffness ks = hn a (the
 * elastic force ks un = (4/3) E* sqrt(R*) un^(3/2), fed to esf_law_linear_normal), the
 * normal tangent stiffness sn = dfn/dun = (3/2) ks = 2 E* a, the tangential one
 * st = ht a = 8 G* a, and *qa = sqrt(a) (the u^(1/4) of the dashpots). */
LANE_INLINE void LANE_FN(esf_law_hertz_springs)(LANE_R hn, LANE_R ht, LANE_R rs,
                                                LANE_R un, LANE_R *ks, LANE_R *sn,
                                                LANE_R *st, LANE_R *qa) {
  const LANE_R a = LANE_SQRT(rs * un);
  *ks = hn * a;
  *sn = 1.5 * *ks;
  *st = ht * a;
  *qa = LANE_SQRT(a);
}

/* The Hertz normal tangent stiffness S_n = (3/2) hn sqrt(R* u) at overlap u (the same
 * operations as esf_law_hertz_springs's sn), 0 when u <= 0 (the rolling springs' kn;
 * the ledger's at the last commit's overlap). */
LANE_INLINE LANE_R LANE_FN(esf_law_hertz_sn)(LANE_R hn, LANE_R rs, LANE_R u) {
  const LANE_R zero = {0};
  return LANE_SEL(u > 0, 1.5 * (hn * LANE_SQRT(rs * u)), zero);
}

/* The Hertz tangential stiffness ht sqrt(R* u) at overlap u, 0 when u <= 0 (the ledger's
 * st0 at the last commit's overlap; the ODE rates of forces.c). */
LANE_INLINE LANE_R LANE_FN(esf_law_hertz_st)(LANE_R ht, LANE_R rs, LANE_R u) {
  const LANE_R zero = {0};
  return LANE_SEL(u > 0, ht * LANE_SQRT(rs * u), zero);
}

/* The Hertz law's dashpots: with Rayleigh damping (beta > 0) c = beta S; else
 * c = factor sqrt(m*) q, the pair's factors 2 gamma sqrt((3/2) hn) and 2 gamma_t
 * sqrt(ht): with q = sqrt(a) (tsuji) c = 2 gamma sqrt(m* S) (Tsuji et al. 1992); with
 * `constant` damping q is esf_law_hertz_qref's, fixed per contact. sm = sqrt(m*). */
LANE_INLINE void LANE_FN(esf_law_hertz_dashpots)(double beta, LANE_R cnf, LANE_R ctf,
                                                 LANE_R sm, LANE_R q, LANE_R sn,
                                                 LANE_R st, LANE_R *cn, LANE_R *ct) {
  if (beta > 0) {
    *cn = beta * sn;
    *ct = beta * st;
  } else {
    *cn = cnf * sm * q;
    *ct = ctf * sm * q;
  }
}

/* The constant dashpots' q: sqrt(a) at the undamped peak overlap u_p = (15 m* v^2 /
 * (16 E* sqrt(R*)))^(2/5) of an impact at v (integrator.impact_speed), so
 * q = (R*^2 (15/16) m* v^2 / E*)^(1/10); es = E*, sm = sqrt(m*). */
LANE_INLINE LANE_R LANE_FN(esf_law_hertz_qref)(LANE_R es, LANE_R sm, LANE_R rs,
                                               double v) {
  return LANE_POW(rs * rs * (0.9375 * v * v) * (sm * sm) / es, 0.1);
}

/* The Hertz normal spring's energy (8/15) E* sqrt(R*) un^(5/2) = (2/5) ks un^2, J. */
LANE_INLINE LANE_R LANE_FN(esf_law_hertz_energy)(LANE_R ks, LANE_R un) {
  return 0.4 * ks * un * un;
}

/* The tangential parameters of a pair, per lane. */
typedef struct LANE_FN(esf_law_tpar) {
  LANE_R kt, ct;    /* spring N/m, dashpot N s/m; Hertz: kt = 1 (xi holds the force) */
  LANE_R mu, coh;   /* friction coefficient, cohesion N */
  LANE_R tl;        /* tension cut-off of the shear strength, N (tension: 1 only) */
  int rotate;       /* 1: the seed's two rotations (000 3-17, 3-18); 0: projection */
  int tension;      /* 1: fn may be negative (the adhesive law): the tension cut-off */
  int ledger;       /* 1: slip work and elastic energy computed */
  int hertz;        /* 1: xi is the elastic force, its increment st dt vct (kt = 1) */
  LANE_R st, st0;   /* Hertz: tangential stiffness now and at the last commit's
                       overlap (st0, ledger only; 0: none), N/m */
  const LANE_R *vi; /* NULL, or the velocity whose tangential part integrates the
                       increment over dt (the ODE methods' trapezoidal carry) */
} LANE_FN(esf_law_tpar);

/* What the tangential force gives. */
typedef struct LANE_FN(esf_law_tout) {
  LANE_R ft[3];  /* tangential force on A, N */
  LANE_R fdt[3]; /* its dashpot part actually applied (zero while sliding), N */
  LANE_R xi[3];  /* the new elastic displacement, m */
  LANE_M slide;  /* the Coulomb cap was active */
  LANE_R slip;   /* friction work of this evaluation, J (ledger) */
  LANE_R e_el;   /* elastic energy (1/2) kt |xi|^2 (Hertz |xi|^2/(2 st)), J (ledger) */
  LANE_R w_st;   /* Hertz: the energy the stiffness change st0 -> st gave the carried
                    force, |xi_rot|^2 (1/st - 1/st0)/2, J (ledger) */
} LANE_FN(esf_law_tout);

/* The tangential force (000 3-17..3-26, 004 2.13-2.16, 2.26): the stored displacement
 * hx (expressed in the plane of normal hn; live: the contact was touching at the last
 * commit, else it starts from zero) brought into the current plane, by the seed's
 * rotations (xi += (hn x n) x xi, then the twist of the spin about n over dt) or by
 * projection and rescaling; the trial xi + dt vct; the force kt xi + ct vct; the
 * Mohr-Coulomb cap tau = max(0, coh + mu fn), zero once fn < -tl (tension only), with
 * radial return xi = ft/kt and no dashpot while sliding. The slip work is the slip
 * xi_trial - xi_new times the mean elastic force kt (xi_rot + xi_new)/2.
 * Hertz-Mindlin (P->hertz): xi holds the elastic force itself (kt = 1), its increment
 * st dt vct (Mindlin's incremental stiffness: a changing contact radius makes no force
 * at zero tangential motion); the elastic energy is |xi|^2/(2 st), the slip work the
 * force's slip (xi_trial - xi_new)/st times the mean force, and w_st books the energy
 * the carried force's energy changes by as st changes. */
LANE_INLINE void LANE_FN(esf_law_tangential)(const LANE_FN(esf_law_tpar) * P, LANE_R dt,
                                             const LANE_R n[3], LANE_R spin,
                                             const LANE_R vc[3], LANE_R vn, LANE_R fn,
                                             const LANE_R hx[3], const LANE_R hn[3],
                                             LANE_M live, LANE_FN(esf_law_tout) * o) {
  const LANE_R zero = {0};
  LANE_R xr[3], t1[3], t2[3];
  if (P->rotate) {
    LANE_FN(esf_law_cross)(t1, hn, n);
    LANE_FN(esf_law_cross)(t2, t1, hx);
    for (int q = 0; q < 3; q++) xr[q] = hx[q] + t2[q];
    const LANE_R ang = spin * dt;
    for (int q = 0; q < 3; q++) t1[q] = ang * n[q];
    LANE_FN(esf_law_cross)(t2, t1, xr);
    for (int q = 0; q < 3; q++) xr[q] = xr[q] + t2[q];
  } else {
    const LANE_R m0 = LANE_SQRT(LANE_FN(esf_law_dot)(hx, hx));
    const LANE_R s = LANE_FN(esf_law_dot)(hx, n);
    for (int q = 0; q < 3; q++) xr[q] = hx[q] - s * n[q];
    const LANE_R m1 = LANE_SQRT(LANE_FN(esf_law_dot)(xr, xr));
    const LANE_R r = m0 / m1;
    for (int q = 0; q < 3; q++) xr[q] = LANE_SEL(m1 > 0, xr[q] * r, xr[q]);
  }
  LANE_R vct[3], inc[3];
  for (int q = 0; q < 3; q++) {
    vct[q] = vc[q] - vn * n[q];
    xr[q] = LANE_SEL(live, xr[q], zero);
  }
  if (P->vi) {
    const LANE_R s = LANE_FN(esf_law_dot)(P->vi, n);
    for (int q = 0; q < 3; q++) inc[q] = P->vi[q] - s * n[q];
  } else {
    for (int q = 0; q < 3; q++) inc[q] = vct[q];
  }
  for (int q = 0; q < 3; q++) {
    const LANE_R di = dt * inc[q];
    o->xi[q] = xr[q] + (P->hertz ? P->st * di : di);
    o->fdt[q] = P->ct * vct[q];
    o->ft[q] = P->kt * o->xi[q] + o->fdt[q];
  }
  LANE_R tau = P->coh + P->mu * fn;
  if (P->tension) {
    tau = LANE_SEL(fn < -P->tl, zero, tau);
    tau = LANE_SEL(tau < 0.0, zero, tau);
  }
  const LANE_R ftm2 = LANE_FN(esf_law_dot)(o->ft, o->ft);
  o->slide = ftm2 > tau * tau;
  o->slip = zero;
  o->w_st = zero;
  /* the spring's energy per |xi|^2: kt/2, or 1/(2 st) for the Hertz force record */
  const LANE_R ew = P->hertz && P->ledger ? 1.0 / P->st : P->kt;
  if (P->hertz && P->ledger) {
    const LANE_R i0 = LANE_SEL(P->st0 > 0, 1.0 / P->st0, ew);
    o->w_st = 0.5 * LANE_FN(esf_law_dot)(xr, xr) * (ew - i0);
  }
  if (LANE_ANY(o->slide)) { /* radial return, no dashpot (004 2.16) */
    const LANE_R sc = tau / LANE_SQRT(ftm2), ikt = LANE_SEL(P->kt > 0, 1.0 / P->kt, zero);
    LANE_R xn[3];
    for (int q = 0; q < 3; q++) {
      o->ft[q] = LANE_SEL(o->slide, o->ft[q] * sc, o->ft[q]);
      xn[q] = ikt * o->ft[q];
    }
    if (P->ledger) { /* (1/2) kt (xi_rot + xi_new) . (xi_trial - xi_new) */
      LANE_R fm[3], sl[3];
      for (int q = 0; q < 3; q++) {
        sl[q] = o->xi[q] - xn[q];
        fm[q] = xr[q] + xn[q];
      }
      o->slip = LANE_SEL(o->slide, 0.5 * ew * LANE_FN(esf_law_dot)(fm, sl), zero);
    }
    for (int q = 0; q < 3; q++) {
      o->xi[q] = LANE_SEL(o->slide, xn[q], o->xi[q]);
      o->fdt[q] = LANE_SEL(o->slide, zero, o->fdt[q]);
    }
  }
  if (P->ledger) o->e_el = 0.5 * ew * LANE_FN(esf_law_dot)(o->xi, o->xi);
}

/* The contact force on A, f = ft - fn n, and the torque direction m = n x ft: the
 * torques are lA m on A and lB m on B (same sense, 004 2.34). */
LANE_INLINE void LANE_FN(esf_law_force)(const LANE_R n[3], LANE_R fn, const LANE_R ft[3],
                                        LANE_R f[3], LANE_R m[3]) {
  for (int q = 0; q < 3; q++) f[q] = ft[q] - fn * n[q];
  LANE_FN(esf_law_cross)(m, n, ft);
}

/* The rolling and twisting resistance parameters of a contact, per lane
 * (docs/physics.md#rolling-resistance; contact/contact_rolling.h derives them). */
typedef struct LANE_FN(esf_law_rpar) {
  LANE_R kr, ktw;   /* rolling and twisting springs, N m/rad (epsd) */
  LANE_R cr, ctw;   /* their dashpots, N m s/rad (epsd) */
  LANE_R mr, mtw;   /* the limits mu_r R* fn and mu_tw R* fn, N m */
  int cdt;          /* 1: the constant directional torque (type A); 0: epsd (type C) */
  const LANE_R *wi; /* NULL, or the relative spin whose parts integrate the springs'
                       increments over dt (the ODE methods' trapezoidal carry) */
  int stiff;        /* 1: book w_k (Hertz pairs with the ledger: kr, ktw vary) */
  LANE_R kr0, ktw0; /* stiff: kr, ktw at the last commit's overlap (0: none) */
} LANE_FN(esf_law_rpar);

/* What the rolling resistance gives. */
typedef struct LANE_FN(esf_law_rout) {
  LANE_R md[3]; /* the dissipative torque on A: the dashpots (epsd) or the constant
                   torques (cdt), N m; B gets -md */
  LANE_R ms[3]; /* the springs' torque on A (epsd; zero for cdt), N m */
  LANE_R hm[3]; /* the new rolling spring torque (in the contact plane), N m */
  LANE_R ht;    /* the new twisting spring torque about n, N m */
  LANE_R slip;  /* plastic work of this evaluation (epsd), J */
  LANE_R e_el;  /* the springs' energy |hm|^2/(2 kr) + ht^2/(2 ktw), J */
  LANE_R w_k;   /* stiff: the energy the carried torques' springs gained as their
                   stiffnesses changed, |hm_c|^2 (1/kr - 1/kr0)/2 + alike, J */
} LANE_FN(esf_law_rout);

/* The rolling (and twisting, with mu_tw) spring of a contact whose normal stiffness
 * is kn, N m/rad: 2.25 kn mu^2 R*^2 (Ai et al. 2011 eq. 17). The linear law passes
 * its kn; the Hertz law its tangent stiffness at the current overlap. */
LANE_INLINE LANE_R LANE_FN(esf_law_rolling_stiffness)(LANE_R kn, LANE_R mu,
                                                      LANE_R rstar) {
  return 2.25 * kn * mu * mu * rstar * rstar;
}

/* A particle pair's effective radius R* = rA rB/(rA + rB) and the equivalent moments
 * of inertia of the rolling resistance: for rolling (about the contact point, Ai et al.
 * 2011 eq. 21) 1/(1/(IA + mA rA^2) + 1/(IB + mB rB^2)), for twisting (about the
 * normal) 1/(1/IA + 1/IB). A wall contact: R* = rA, IA + mA rA^2 and IA. */
LANE_INLINE void LANE_FN(esf_law_rolling_pair)(LANE_R ra, LANE_R rb, LANE_R ma, LANE_R mb,
                                               LANE_R ia, LANE_R ib, LANE_R *rstar,
                                               LANE_R *ir, LANE_R *itw) {
  const LANE_R ja = ia + ma * ra * ra, jb = ib + mb * rb * rb;
  *rstar = ra * rb / (ra + rb);
  *ir = ja * jb / (ja + jb);
  *itw = ia * ib / (ia + ib);
}

/* The rolling resistance's parameters (esf_law_rpar) of a contact: normal stiffness kn
 * (esf_law_rolling_stiffness), mu_r, mu_tw, the damping ratio eta_r, R* and the
 * inertias (esf_law_rolling_pair), the normal force fn (a tension gives no resistance)
 * and the model (cdt: no springs). Dashpots C = eta_r 2 sqrt(I k) (Ai eq. 20). */
LANE_INLINE void LANE_FN(esf_law_rolling_par)(LANE_R kn, LANE_R mu_r, LANE_R mu_tw,
                                              LANE_R eta_r, LANE_R rstar, LANE_R ir,
                                              LANE_R itw, LANE_R fn, int cdt,
                                              LANE_FN(esf_law_rpar) * P) {
  const LANE_R zero = {0};
  const LANE_R f = LANE_SEL(fn > 0, fn, zero);
  P->mr = mu_r * rstar * f;
  P->mtw = mu_tw * rstar * f;
  P->cdt = cdt;
  P->wi = 0;    /* no carry */
  P->stiff = 0; /* no stiffness-change term */
  P->kr = P->ktw = P->cr = P->ctw = P->kr0 = P->ktw0 = zero;
  if (!cdt) {
    P->kr = LANE_FN(esf_law_rolling_stiffness)(kn, mu_r, rstar);
    P->ktw = LANE_FN(esf_law_rolling_stiffness)(kn, mu_tw, rstar);
    P->cr = 2.0 * eta_r * LANE_SQRT(ir * P->kr);
    P->ctw = 2.0 * eta_r * LANE_SQRT(itw * P->ktw);
  }
}

/* One elastic-plastic spring of the rolling resistance (Ai et al. 2011, type C), for
 * a torque that is a vector (ncomp 3) or a scalar about n (ncomp 1): trial
 * h - k dt wr, capped at lim (radial return), and the plastic work
 * (h + h_new).(h_trial - h_new)/(2 k) added to *slip; *full: the mask of full
 * mobilisation. */
LANE_INLINE void LANE_FN(esf_law_roll_spring)(int ncomp, LANE_R k, LANE_R lim, LANE_R dt,
                                              const LANE_R *h, const LANE_R *wr,
                                              LANE_R *hn, LANE_R *slip, LANE_M *full) {
  const LANE_R zero = {0};
  LANE_R tr[3], m2 = zero;
  for (int q = 0; q < ncomp; q++) {
    tr[q] = h[q] - k * dt * wr[q];
    m2 = m2 + tr[q] * tr[q];
  }
  *full = m2 > lim * lim;
  const LANE_R sc = LANE_SEL(*full, lim / LANE_SQRT(m2), zero + 1.0);
  const LANE_R ik = LANE_SEL(k > 0, 0.5 / k, zero);
  LANE_R w = zero;
  for (int q = 0; q < ncomp; q++) {
    hn[q] = tr[q] * sc;
    w = w + (h[q] + hn[q]) * (tr[q] - hn[q]);
  }
  *slip = *slip + LANE_SEL(*full, ik * w, zero);
}

/* Rolling and twisting resistance (docs/physics.md#rolling-resistance): the relative
 * spin wrel = wA - wB split into its rolling part wr (in the contact plane) and its
 * twisting part wn = wrel.n. epsd (type C, Ai et al. 2011 eqs. 13-19): the stored
 * rolling torque hm (from the last commit; live: the contact was touching, else zero)
 * projected on the current plane and rescaled to keep |hm|, the spring increment
 * -kr dt wr, the cap mu_r R* fn, and the dashpot -cr wr switched off while the cap
 * holds; the twisting torque ht about n alike. cdt (type A): -mu_r R* fn wr/|wr|
 * and -mu_tw R* fn sign(wn), no history. P->stiff (Hertz pairs, whose kr and ktw follow
 * S_n): w_k books the carried torques' energy change from kr0, ktw0 to kr, ktw, as
 * esf_law_tangential's w_st does for the Hertz tangential force. */
LANE_INLINE void LANE_FN(esf_law_rolling)(const LANE_FN(esf_law_rpar) * P, LANE_R dt,
                                          const LANE_R n[3], const LANE_R wrel[3],
                                          const LANE_R hm[3], LANE_R ht, LANE_M live,
                                          LANE_FN(esf_law_rout) * o) {
  const LANE_R zero = {0};
  const LANE_R wn = LANE_FN(esf_law_dot)(wrel, n);
  LANE_R wr[3];
  for (int q = 0; q < 3; q++) wr[q] = wrel[q] - wn * n[q];
  o->slip = zero;
  o->w_k = zero;
  if (P->cdt) {
    const LANE_R a = LANE_SQRT(LANE_FN(esf_law_dot)(wr, wr));
    const LANE_R s = LANE_SEL(a > 0, P->mr / a, zero);
    const LANE_R t = LANE_SEL(wn > 0, -P->mtw, LANE_SEL(wn < 0, P->mtw, zero));
    for (int q = 0; q < 3; q++) {
      o->md[q] = -s * wr[q] + t * n[q];
      o->ms[q] = zero;
      o->hm[q] = zero;
    }
    o->ht = zero;
    o->e_el = zero;
    return;
  }
  LANE_R hr[3];
  const LANE_R m0 = LANE_SQRT(LANE_FN(esf_law_dot)(hm, hm));
  const LANE_R s = LANE_FN(esf_law_dot)(hm, n);
  for (int q = 0; q < 3; q++) hr[q] = hm[q] - s * n[q];
  const LANE_R m1 = LANE_SQRT(LANE_FN(esf_law_dot)(hr, hr));
  const LANE_R r = LANE_SEL(m1 > 0, m0 / m1, zero);
  for (int q = 0; q < 3; q++) hr[q] = LANE_SEL(live, hr[q] * r, zero);
  const LANE_R h1 = LANE_SEL(live, ht, zero);
  const LANE_R ikr = LANE_SEL(P->kr > 0, 0.5 / P->kr, zero),
               ikt = LANE_SEL(P->ktw > 0, 0.5 / P->ktw, zero);
  if (P->stiff) {
    const LANE_R i0r = LANE_SEL(P->kr0 > 0, 0.5 / P->kr0, ikr),
                 i0t = LANE_SEL(P->ktw0 > 0, 0.5 / P->ktw0, ikt);
    o->w_k = (ikr - i0r) * LANE_FN(esf_law_dot)(hr, hr) + (ikt - i0t) * (h1 * h1);
  }
  LANE_M fr, ft;
  LANE_R wri[3], wni = wn; /* the increments' spin: wrel's parts, or wi's */
  if (P->wi) {
    wni = LANE_FN(esf_law_dot)(P->wi, n);
    for (int q = 0; q < 3; q++) wri[q] = P->wi[q] - wni * n[q];
  } else {
    for (int q = 0; q < 3; q++) wri[q] = wr[q];
  }
  LANE_FN(esf_law_roll_spring)(3, P->kr, P->mr, dt, hr, wri, o->hm, &o->slip, &fr);
  LANE_FN(esf_law_roll_spring)(1, P->ktw, P->mtw, dt, &h1, &wni, &o->ht, &o->slip, &ft);
  const LANE_R dtw = LANE_SEL(ft, zero, -P->ctw * wn);
  for (int q = 0; q < 3; q++) {
    o->md[q] = LANE_SEL(fr, zero, -P->cr * wr[q]) + dtw * n[q];
    o->ms[q] = o->hm[q] + o->ht * n[q];
  }
  o->e_el = ikr * LANE_FN(esf_law_dot)(o->hm, o->hm) + ikt * o->ht * o->ht;
}
