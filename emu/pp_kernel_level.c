/* pp_kernel_level.c: which kernel copies this build has and this host runs. */
#include "pp_kernel_level.h"

#include "pp_simd.h"

bool pp_kernel_level_available(pp_kernel_level_t level)
{
    switch (level) {
    case PP_KERNELS_PORTABLE:
        return true;
#if PP_HAVE_X86_COPIES
    /* __builtin_cpu_supports also requires the OS to save the wider registers
     * (libgcc checks XGETBV), so a "yes" means the copy can really run. */
    case PP_KERNELS_AVX2:
        return __builtin_cpu_supports("avx2");
    case PP_KERNELS_AVX512:
        return __builtin_cpu_supports("avx512f");
#endif
    default:
        return false;
    }
}

pp_kernel_level_t pp_kernel_level_at_most(pp_kernel_level_t wanted)
{
    int level = (int)wanted;
    if (level >= PP_KERNEL_LEVELS)
        level = PP_KERNEL_LEVELS - 1;
    while (level > PP_KERNELS_PORTABLE && !pp_kernel_level_available((pp_kernel_level_t)level))
        level--;
    return level < 0 ? PP_KERNELS_PORTABLE : (pp_kernel_level_t)level;
}

pp_kernel_level_t pp_kernel_level_best(void)
{
    return pp_kernel_level_at_most(PP_KERNELS_AVX512);
}

const char *pp_kernel_level_name(pp_kernel_level_t level)
{
    switch (level) {
    case PP_KERNELS_AVX2: return "AVX2";
    case PP_KERNELS_AVX512: return "AVX-512";
    default: return "portable";
    }
}

const char *pp_kernel_level_describe(pp_kernel_level_t level)
{
    switch (level) {
    case PP_KERNELS_AVX2: return "AVX2 (32-byte vectors)";
    case PP_KERNELS_AVX512: return "AVX-512 (64-byte vectors)";
    default: return "portable (16-byte vectors)";
    }
}
