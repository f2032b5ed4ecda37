/* fused_isa.h — names of the fused step's kernels, compiled once per instruction set.
 *
 * The kernel files (fused_kernels.c, fused_kick.c, fused_pairs.c, fused_slots.c,
 * pair_batch.c) are built several times, each with -DESF_ISA=<name> and that
 * instruction set's flags (src/fused/meson.build): base (the build's own flags), avx2,
 * avx512. The defines below give every function they export the suffix _<name>, so the
 * copies link side by side; esf_fused_create picks one table (esf_fused_kernels_<name>)
 * for the CPU it runs on. Every copy computes the same operations in the same order
 * without contraction into FMA (-ffp-contract=off), so all give the same bits. */
#ifndef ESF_FUSED_ISA_H
#define ESF_FUSED_ISA_H

#ifndef ESF_ISA
#define ESF_ISA base
#endif

#define ESF_ISA_CAT_(a, b) a##_##b
#define ESF_ISA_CAT(a, b)  ESF_ISA_CAT_(a, b)
#define ESF_ISA_NAME(f)    ESF_ISA_CAT(f, ESF_ISA)
#define ESF_ISA_STR_(x)    #x
#define ESF_ISA_STR(x)     ESF_ISA_STR_(x)

#define esf_fused_boundary       ESF_ISA_NAME(esf_fused_boundary)
#define esf_fused_pairs          ESF_ISA_NAME(esf_fused_pairs)
#define esf_fused_kick_range     ESF_ISA_NAME(esf_fused_kick_range)
#define esf_fused_vv_drift_range ESF_ISA_NAME(esf_fused_vv_drift_range)
#define esf_pair_batch_linear    ESF_ISA_NAME(esf_pair_batch_linear)
#define esf_pair_batch_geometry  ESF_ISA_NAME(esf_pair_batch_geometry)
#define esf_pair_batch_law       ESF_ISA_NAME(esf_pair_batch_law)

#endif
