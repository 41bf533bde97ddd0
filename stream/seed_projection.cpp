#include "stream/seed_projection.hpp"

namespace meshless {

void print_newton_stats(std::FILE* out, const char* cmd, const std::string& field, const FieldProjectParams& p,
                        const FieldNewtonStats& s, double busy_seconds) {
    std::fprintf(out,
                 "%s: Newton onto %s (tolerance %g x cell diagonal, <= %d iterations): %lld seeds -> %lld converged; "
                 "dropped %lld (flat gradient %lld, too far %lld, not converged %lld, stalled %lld, non-finite %lld); "
                 "%.2f evaluations/seed; %.0f points/s per core (%.3f s busy)\n",
                 cmd, field.c_str(), p.seed_tolerance, p.newton.max_iterations, static_cast<long long>(s.input),
                 static_cast<long long>(s.converged), static_cast<long long>(s.dropped()), static_cast<long long>(s.flat),
                 static_cast<long long>(s.too_far), static_cast<long long>(s.not_converged), static_cast<long long>(s.stalled),
                 static_cast<long long>(s.nonfinite), s.input ? double(s.evaluations) / double(s.input) : 0.0,
                 busy_seconds > 0 ? double(s.converged) / busy_seconds : 0.0, busy_seconds);
}

}  // namespace meshless
