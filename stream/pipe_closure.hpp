// Outputs that end at a pipe: with several outputs, one of them possibly stdout, the reader of
// stdout going away (BrokenPipe, kernels/errors.hpp) stops that output only; the others are still
// completed and committed before the run ends quietly. Thread-safety: one object per run.
#pragma once
#include <exception>

#include "kernels/errors.hpp"

namespace meshless {

/// For commands with several outputs, one of them possibly stdout: a step that throws BrokenPipe
/// (stdout's reader has gone) stops that output only; step() returns false then, and
/// rethrow_if_closed(), called once the other outputs are complete, ends the command quietly.
class PipeClosure {
public:
    template <class F>
    bool step(const F& f);
    /// Records the BrokenPipe being handled (call inside its catch block).
    void caught() { closed_ = std::current_exception(); }
    void rethrow_if_closed() const {
        if (closed_) std::rethrow_exception(closed_);
    }

private:
    std::exception_ptr closed_;
};

template <class F>
bool PipeClosure::step(const F& f) {
    try {
        f();
        return true;
    } catch (const BrokenPipe&) {
        caught();
        return false;
    }
}

}  // namespace meshless
