// MultiquadricSolver::fit for plain x86-64 (or whatever the project targets): see
// kernels/multiquadric_fit_isa.hpp.
#include "kernels/multiquadric_fit_impl.hpp"

namespace meshless_mqfit {

const Kernel& generic_kernel() {
    static constexpr Kernel k{&meshless::mqfit_create, &meshless::mqfit_destroy, &meshless::mqfit_fit, "generic"};
    return k;
}

}  // namespace meshless_mqfit
