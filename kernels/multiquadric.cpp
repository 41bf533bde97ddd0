#include "kernels/multiquadric.hpp"

#include <type_traits>

#include "kernels/multiquadric_fit_isa.hpp"

namespace meshless {

static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>,
              "the fit kernels read an array of Vec3 as x, y, z triples");

namespace {
bool cpu_has_avx2_fma() {
#if MESHLESS_MQ_FIT_AVX2
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}
// The build of the fit this process runs (kernels/multiquadric_fit_isa.hpp), chosen once.
const meshless_mqfit::Kernel& fit_kernel() {
#if MESHLESS_MQ_FIT_AVX2
    static const meshless_mqfit::Kernel& k = cpu_has_avx2_fma() ? meshless_mqfit::avx2_kernel()
                                                                : meshless_mqfit::generic_kernel();
    return k;
#else
    return meshless_mqfit::generic_kernel();
#endif
}
const meshless_mqfit::Kernel& kernel_named(std::string_view isa) {
#if MESHLESS_MQ_FIT_AVX2
    if (isa == "avx2") return meshless_mqfit::avx2_kernel();
#endif
    (void)isa;
    return meshless_mqfit::generic_kernel();
}
}  // namespace

const char* multiquadric_fit_isa() { return fit_kernel().isa; }

bool multiquadric_fit_isa_available(std::string_view isa) {
    return isa == "generic" || (isa == "avx2" && cpu_has_avx2_fma());
}

struct MultiquadricSolver::Impl {
    const meshless_mqfit::Kernel& kernel;
    void* workspace = kernel.create();
    explicit Impl(const meshless_mqfit::Kernel& k) : kernel(k) {}
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl() { kernel.destroy(workspace); }
};

MultiquadricSolver::MultiquadricSolver() : impl_(std::make_unique<Impl>(fit_kernel())) {}
MultiquadricSolver::MultiquadricSolver(std::string_view isa) : impl_(std::make_unique<Impl>(kernel_named(isa))) {}
MultiquadricSolver::~MultiquadricSolver() = default;

MultiquadricFitResult MultiquadricSolver::fit(std::span<const Vec3> pos, std::span<const double> value,
                                              std::span<const std::uint32_t> idx, double c,
                                              MultiquadricLocal& out, std::span<double> lambda, bool leave_one_out) {
    meshless_mqfit::Io io;
    io.pos = reinterpret_cast<const double*>(pos.data());
    io.value = value.data();
    io.idx = idx.data();
    io.n = static_cast<std::uint32_t>(idx.size());
    io.c = c;
    io.lambda = lambda.data();
    io.want_loo = leave_one_out ? 1 : 0;
    impl_->kernel.fit(impl_->workspace, io);
    out.origin = {io.origin[0], io.origin[1], io.origin[2]};
    out.a0 = io.a0;
    out.a = {io.a[0], io.a[1], io.a[2]};
    out.c2 = io.c2;
    out.count = io.count;
    MultiquadricFitResult res;
    res.outcome = static_cast<MultiquadricOutcome>(io.outcome);
    res.poly_rank = io.poly_rank;
    res.rcond = io.rcond;
    res.loo = io.loo;
    return res;
}

}  // namespace meshless
