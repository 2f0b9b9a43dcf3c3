// How many threads a world's detects run on under the adaptive thread policy
// (hgcd_world_desc.thread_policy): all it is set to while its threads get
// the cores, fewer while they are descheduled.
//
// OpenMP threads that wait at a barrier spin first (libgomp's default), so
// on cores shared with other busy processes a region's threads wait for a
// descheduled thread while holding the core it needs: with two busy
// processes on 2 cores, a 2-thread detect took 2.4 times as long as a
// 1-thread one. The environment that would stop the spinning
// (OMP_WAIT_POLICY) belongs to the host, so each world measures instead:
// every detect's regions report how much of their threads' time was spent
// off a core (LoadMeter, common/parallel.hpp), and each detect's seconds per
// unit of work (bodies plus candidate pairs, which do not depend on the
// thread count). When a quarter of the time was lost, the next detect is a
// check on half the threads, and the one after it runs on the current count
// again: the check wins only if it did its work faster than both detects
// around it. So one detect slowed by a passing blip (on ticks of a few ms,
// one descheduling is a quarter of the time) is not taken for a loaded
// machine, while load that lasts slows both. After a win the world stays on
// the fewer threads, and probes the larger count again after 8 detects, then
// 16, 32, ... up to 512 while the probes lose. A lost check waits the same
// way before the next. The pairs never depend on the thread count.
#pragma once

namespace hgcd {

class ThreadGovernor {
  public:
    // Threads for the next detect of a world set to `full` (>= 1).
    int threads(int full) const;
    // What the detect that ran on threads(full) threads measured: `seconds`
    // for `work` units, `lost`: LoadMeter::lost().
    void record(int full, double seconds, double work, double lost);
    // Back to all threads, nothing measured.
    void reset();

  private:
    static constexpr int kLevels = 13;        // full >> level threads, at most 4096
    static constexpr int kMinWait = 8;        // detects before a first probe or check
    static constexpr int kMaxWait = 512;      // the longest wait between them
    static constexpr double kLost = 0.25;     // lost time that calls a check
    static constexpr double kProbeGain = 0.9; // a probe wins when it is at least 10% faster

    void move_to(int level);            // run on level from the next detect
    bool start_check(double rate_now);  // the next detect a check of level_ + 1, if there is one
    static int count(int full, int level) { return full >> level > 1 ? full >> level : 1; }
    int full_ = 0;     // the count level_ refers to (another resets)
    int level_ = 0;    // detects run on count(full_, level_) threads
    int trial_ = -1;   // the next detect's level when it is a check or probe
    int checked_ = -1;  // a check's level, awaiting the detect after it on level_
    bool checked_lost_ = false;   // whether that check lost time itself (fewer still?)
    double before_ = 0, checked_rate_ = 0;  // level_'s rate before the check; the check's
    double rate_[kLevels] = {};  // seconds per unit, the latest detect of each level (0: none)
    int probe_in_ = 0, probe_wait_ = kMinWait;  // detects before the next probe of level_ - 1
    int check_in_ = 0, check_wait_ = kMinWait;  // detects before a check of level_ + 1 may run
};

}  // namespace hgcd
