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
    if (!(seconds > 0) || !(work > 0)) {
        checked_ = -1;
        return;
    }
    const double rate = seconds / work;
    rate_[ran] = rate;
    if (ran > level_) {  // a check of fewer threads: decided after the next detect
        checked_ = ran;
        checked_rate_ = rate;
        checked_lost_ = lost > kLost;
        return;
    }
    if (ran < level_) {  // a probe of more threads
        if (rate < kProbeGain * rate_[level_]) {
            move_to(ran);
        } else {
            probe_wait_ = std::min(2 * probe_wait_, kMaxWait);
            probe_in_ = probe_wait_;
        }
        return;
    }
    if (checked_ >= 0) {  // the detect after a check
        const int checked = checked_;
        checked_ = -1;
        if (checked_rate_ < std::min(before_, rate)) {
            move_to(checked);
            if (checked_lost_) start_check(checked_rate_);  // fewer still?
        } else {
            check_wait_ = std::min(2 * check_wait_, kMaxWait);
            check_in_ = check_wait_;
        }
        return;
    }
    if (check_in_ > 0) --check_in_;
    const bool checking = lost > kLost && check_in_ == 0 && start_check(rate);
    if (!checking && level_ > 0 && --probe_in_ <= 0) trial_ = level_ - 1;
}

void ThreadGovernor::move_to(int level) {
    level_ = level;
    probe_wait_ = probe_in_ = kMinWait;
    check_wait_ = kMinWait;
    check_in_ = 0;
}

bool ThreadGovernor::start_check(double rate_now) {
    if (level_ + 1 >= kLevels || count(full_, level_) <= 1) return false;
    trial_ = level_ + 1;
    before_ = rate_now;
    return true;
}

}  // namespace hgcd
