// The adaptive thread policy's decisions (threads.hpp).
#include "common/ieee.hpp"
#include "world/threads.hpp"

#include <algorithm>

namespace hgcd {

int ThreadGovernor::threads(int full) const {
    if (full != full_) return full;
    return count(full, trial_ >= 0 ? trial_ : level_);
}

void ThreadGovernor::reset() { *this = ThreadGovernor(); }

void ThreadGovernor::record(int full, double seconds, double work, double lost) {
    if (full != full_) {  // the first detect at this count ran on all of them
        reset();
        full_ = full;
    }
    const int ran = trial_ >= 0 ? trial_ : level_;
    trial_ = -1;
    if (!(seconds > 0) || !(work > 0)) return;
    rate_[ran] = seconds / work;
    if (ran > level_) {  // a check of fewer threads
        if (rate_[ran] < rate_[level_]) {
            level_ = ran;
            probe_wait_ = probe_in_ = kMinWait;
            check_wait_ = kMinWait;
            check_in_ = 0;
            if (lost > kLost && count(full, level_) > 1 && level_ + 1 < kLevels) trial_ = level_ + 1;  // fewer still?
        } else {
            check_wait_ = std::min(2 * check_wait_, kMaxWait);
            check_in_ = check_wait_;
        }
        return;
    }
    if (ran < level_) {  // a probe of more threads
        if (rate_[ran] < kProbeGain * rate_[level_]) {
            level_ = ran;
            probe_wait_ = probe_in_ = kMinWait;
            check_wait_ = kMinWait;
            check_in_ = 0;
        } else {
            probe_wait_ = std::min(2 * probe_wait_, kMaxWait);
            probe_in_ = probe_wait_;
        }
        return;
    }
    if (check_in_ > 0) --check_in_;
    if (lost > kLost && check_in_ == 0 && level_ + 1 < kLevels && count(full, level_) > 1) {
        trial_ = level_ + 1;
    } else if (level_ > 0 && --probe_in_ <= 0) {
        trial_ = level_ - 1;
    }
}

}  // namespace hgcd
