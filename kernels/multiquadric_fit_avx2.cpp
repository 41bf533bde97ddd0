// MultiquadricSolver::fit built with AVX2 + FMA (kernels/CMakeLists.txt gives this file -mavx2
// -mfma), called only on CPUs that have both (kernels/multiquadric.cpp). The macros below rename
// the namespaces of every Eigen and meshless entity this file instantiates, so none of its code can
// replace the generic build's at link time (kernels/multiquadric_fit_isa.hpp: no ODR hazard).
#if MESHLESS_MQ_FIT_AVX2
#define Eigen meshless_avx2_Eigen
#define meshless meshless_avx2
#include "kernels/multiquadric_fit_impl.hpp"

namespace meshless_mqfit {

const Kernel& avx2_kernel() {
    static constexpr Kernel k{&meshless::mqfit_create, &meshless::mqfit_destroy, &meshless::mqfit_fit, "avx2"};
    return k;
}

}  // namespace meshless_mqfit
#endif
