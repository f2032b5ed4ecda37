/* fused_kernels.c — the table of one instruction set's copy of the fused step's
 * kernels (fused_isa.h): what esf_fused_create picks for the CPU it runs on. */
#include "fused/fused_impl.h"

const esf_fused_kernels ESF_ISA_NAME(esf_fused_kernels) = {
    .isa = ESF_ISA_STR(ESF_ISA),
    .boundary = esf_fused_boundary,
    .pairs = esf_fused_pairs,
    .kick_range = esf_fused_kick_range,
    .batch = esf_pair_batch_linear,
    .vv_drift = esf_fused_vv_drift_range,
};
