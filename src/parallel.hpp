// An exception must not leave an OpenMP region: the runtime would call
// std::terminate, turning an out-of-memory into an abort. Region bodies run
// through RegionGuard::run, which keeps the first exception; the caller
// rethrows it once the region has ended.
#pragma once
#include <exception>

namespace hgcd {

class RegionGuard {
  public:
    template <class F>
    void run(F &&f) noexcept {
        try {
            f();
        } catch (...) {
#pragma omp critical(hgcd_region_guard)
            if (!first_) first_ = std::current_exception();
        }
    }
    void rethrow() const {
        if (first_) std::rethrow_exception(first_);
    }

  private:
    std::exception_ptr first_;
};

}  // namespace hgcd
