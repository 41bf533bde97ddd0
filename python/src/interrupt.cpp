#include "interrupt.hpp"

#include <pybind11/pybind11.h>

#include <condition_variable>
#include <mutex>
#include <thread>

namespace meshless::python {

namespace py = pybind11;

void run_interruptible(const std::function<void(const std::atomic<bool>& stop)>& work) {
    std::atomic<bool> stop{false};
    std::mutex m;
    std::condition_variable cv;
    bool done = false;
    std::exception_ptr error;
    bool interrupted = false;
    {
        py::gil_scoped_release free;
        std::thread worker([&] {
            try {
                work(stop);
            } catch (...) {
                error = std::current_exception();
            }
            const std::lock_guard<std::mutex> lock(m);
            done = true;
            cv.notify_all();
        });
        std::unique_lock<std::mutex> lock(m);
        while (!cv.wait_for(lock, kSignalPoll, [&] { return done; })) {
            if (interrupted) continue;
            lock.unlock();
            {
                const py::gil_scoped_acquire held;
                if (PyErr_CheckSignals() != 0) interrupted = true;  // the exception stays set for below
            }
            if (interrupted) stop = true;
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (interrupted) throw py::error_already_set();
    if (error) std::rethrow_exception(error);
}

}  // namespace meshless::python
