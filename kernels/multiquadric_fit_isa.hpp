// The instruction-set variants of MultiquadricSolver::fit (kernels/multiquadric.hpp, dissertation
// section 2.1.1): the same source, kernels/multiquadric_fit_impl.hpp, compiled twice, for plain
// x86-64 (multiquadric_fit_generic.cpp) and with AVX2 + FMA (multiquadric_fit_avx2.cpp, built
// where the compiler targets x86-64; MESHLESS_MQ_FIT_AVX2 is then defined to 1). Eigen's dense
// kernels are chosen at compile time from the target flags, so the project, built without -march,
// would otherwise run its LLT and products 2 doubles wide; the AVX2 build makes the local fits ~1.5x
// faster (measured on the RBF-grid fit of the bucky set: 0.35 -> 0.24 s CPU).
// No ODR hazard: the AVX2 translation unit renames the namespaces `Eigen` and `meshless` by macro
// before including anything of theirs, so none of its (inline, template) functions shares a
// symbol with the generic build; everything else of it has internal linkage; the interface here
// is plain data in a namespace of its own, which neither build renames. tests/kernels check the
// AVX2 object's symbols (no weak symbol outside the renamed namespaces, no static initialiser).
// Dispatch: once per process (__builtin_cpu_supports("avx2") and ("fma")), so a process's fits,
// and with them every output, are the same for any thread count; the two builds differ by
// rounding only (FMA), within the solver's 1e-8 residual bound.
// Thread-safety: a workspace per thread; kernels are pure otherwise. Throw only std::bad_alloc.
#pragma once
#include <cstdint>

namespace meshless_mqfit {

/// One fit's inputs and results (the fields of MultiquadricLocal / MultiquadricFitResult).
struct Io {
    const double* pos = nullptr;          ///< point i at pos[3i .. 3i+2] (an array of meshless::Vec3)
    const double* value = nullptr;        ///< value of point i
    const std::uint32_t* idx = nullptr;   ///< the n points of the fit
    std::uint32_t n = 0;
    double c = 0;                         ///< Hardy's c (caller's frame)
    double* lambda = nullptr;             ///< n coefficients out
    double origin[3] = {0, 0, 0};
    double a0 = 0, a[3] = {0, 0, 0}, c2 = 0;
    std::uint32_t count = 0;
    int outcome = 0;                      ///< meshless::MultiquadricOutcome
    int poly_rank = 4;
    double rcond = 0;
    int want_loo = 0;                     ///< in: 1 = compute loo
    double loo = -1;                      ///< out: RMS leave-one-out error of an RBF fit (data units), -1 none
};

/// One build of the fit: a workspace (scratch that only grows) and the fit through it.
struct Kernel {
    void* (*create)();
    void (*destroy)(void*);
    void (*fit)(void* workspace, Io& io);
    const char* isa;
};

const Kernel& generic_kernel();
#if MESHLESS_MQ_FIT_AVX2
const Kernel& avx2_kernel();
#endif

}  // namespace meshless_mqfit
