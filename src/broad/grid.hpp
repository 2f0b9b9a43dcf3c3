// Broad phase: the hierarchical grid of the paper over each body's box, as
// sorted arrays. Levels have cells of width w = 2^e; a body lives on the
// finest level with w at least twice a bound r_level on its offsets from its
// point p (so its box lies within w / 2 of p) and is a guest on every
// coarser level, met there by the residents. Each pair comes once:
// same-level pairs from the earlier entry in sweep order, cross-level pairs
// from the finer body. Bodies too large for the coarsest level are oversize
// (range queries, and a sweep on x among themselves); a level with very few
// bodies beside the finer ones keeps no guests and queries them instead.
// Within a level, a body's row is the (z, y) cell of p for cells 2w high
// and deep; each list (residents, guests) holds its bodies sorted by row and
// low x, an index of the occupied rows, and the boxes rounded outward to
// float (supersets: no overlapping pair is lost). A body meets the later
// bodies of its row up to its high x, and those of the 3x3 rows around it
// within reach, by cursors that only move forward, four or eight boxes a
// test. Motion moves only the bodies whose row or level changed; an
// insertion sort restores the x order; the world keeps its storage in the
// residents' order (order(), renumber()) so the update reads in sequence.
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace hgcd {

class RegionGuard;
using CellKey = unsigned __int128;

// x rounded to a float at most x, or at least x (the nearest float, moved
// one step out when it falls on the wrong side): how offsets and the grid's
// boxes are stored. A magnitude below FLT_MIN goes to 0 or -FLT_MIN (at
// most), 0 or FLT_MIN (at least) instead: no subnormal float is ever
// stored or produced, so the bounds hold in a process that flushes
// subnormals to zero (FTZ/DAZ, which a host linked with -ffast-math turns
// on), where a stored subnormal would read as 0, on the wrong side.
inline float float_at_most(double x) {
    if (std::fabs(x) < double(FLT_MIN)) return std::signbit(x) ? -FLT_MIN : 0.0f;
    const float f = float(x);
    return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
inline float float_at_least(double x) { return -float_at_most(-x); }

// The bodies as the grid reads them: body s has reference point
// p = pos[3 s + (0, 1, 2)] and offsets off[6 s + (0..5)] (low x y z,
// high x y z); its box is [fl(p + low), fl(p + high)] per axis, and holds
// its solid. (Rounding is monotone: offsets at most, or at least, every
// vertex's offset give a box holding the vertices fl(p + offset).)
struct Boxes {
    const double *pos;
    const float *off;
    const double *point(size_t s) const { return pos + 3 * s; }
    void at(size_t s, double *lo, double *hi) const {
        const double *p = point(s);
        const float *o = off + 6 * s;
        for (int k = 0; k < 3; ++k) {
            lo[k] = p[k] + double(o[k]);
            hi[k] = p[k] + double(o[3 + k]);
        }
    }
};

// The key of the pair {a, b}: the lower slot in the high half (the order the
// world reports and the sweeps' consumers sort by).
inline uint64_t pair_key(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

struct GridLimits {
    int min_exponent;  // INT32_MIN: none
    int max_exponent;  // INT32_MAX: none
    // Bodies whose level is at most a factor 4 finer than the coarsest level
    // that keeps guests live on that level instead: fewer levels, guests and
    // row visits for more box tests, which pays where bodies are sparse
    // (the world decides, from the candidate pairs per body).
    bool coarsen = false;
};

// One thread's candidate pairs. Its storage is not initialised as it grows,
// and the sweeps write whole blocks into room() before counting the pairs
// among them (commit), so that their hot loop has no branch per pair. Aligned
// to its own cache lines: every thread updates its size all the time.
class alignas(64) PairBuffer {
  public:
    size_t size() const { return size_; }
    const uint64_t *begin() const { return data_.get(); }
    const uint64_t *end() const { return data_.get() + size_; }
    uint64_t operator[](size_t k) const { return data_[k]; }
    void clear() { size_ = 0; }
    uint64_t *data() { return data_.get(); }
    void shrink(size_t n) { size_ = std::min(size_, n); }  // keeps the first n pairs
    // At least k writable places past the end (may throw bad_alloc).
    uint64_t *room(size_t k) {
        if (capacity_ - size_ < k) grow(k);
        return data_.get() + size_;
    }
    void commit(size_t k) { size_ += k; }  // the first k places of room() are pairs
    void push_back(uint64_t pair) {
        *room(1) = pair;
        ++size_;
    }

  private:
    void grow(size_t k) {
        const size_t cap = std::max(2 * capacity_, size_ + k + 4096);
        std::unique_ptr<uint64_t[]> bigger(new uint64_t[cap]);  // (left uninitialised)
        std::copy(begin(), end(), bigger.get());
        data_ = std::move(bigger);
        capacity_ = cap;
    }
    std::unique_ptr<uint64_t[]> data_;
    size_t size_ = 0, capacity_ = 0;
};

// Work the grid update's census hands each range of slots [begin, end) to,
// on the thread that then reads their points, just before it does (see
// Grid::update). Must not throw.
struct SlotPass {
    void (*run)(void *context, uint32_t begin, uint32_t end);
    void *context;
};

struct GridUpdateStats {
    uint64_t moved = 0;  // bodies that changed row or membership
    bool rebuilt = false;
};

class Grid {
  public:
    // Brings the grid to the current boxes. live_gen[s] is the generation of
    // the body in slot s, or 0 for an empty slot; r_level[s] bounds the
    // magnitude of its offsets in every orientation (so it picks the body's
    // level once for its life: position- and orientation-independent).
    // before, if given, runs on every slot range of the census once the
    // census has begun (all of them, also when the update then fails), and
    // nowhere else: a world moves its bodies there, so that the census reads
    // the new points while they are in cache, where a pass of its own read
    // them back from memory.
    GridUpdateStats update(const Boxes &boxes, const double *r_level, const uint32_t *live_gen,
                           uint32_t slot_count, const GridLimits &limits, int threads,
                           const SlotPass *before = nullptr);

    // Appends to out[thread] every pair (a << 32 | b) of bodies whose boxes
    // overlap (closed intervals on every axis), once, in either order (the
    // sweeps' hot loop does not order them: its consumers do), and possibly
    // pairs whose boxes overlap only once each bound is rounded outward to
    // float (the lists' precision; never a pair whose float boxes are
    // apart). out must have one buffer per thread. boxes: as given to the
    // last update.
    void find_pairs(const Boxes &boxes, int threads, std::vector<PairBuffer> &out) const;

    // Where a run of queries (query()) found each level's rows last, and the
    // start of its scan in each row: queries in sweep order then move their
    // cursors a little each. One per thread; any content is valid.
    struct QueryCursors {
        std::vector<size_t> row;                   // per level
        std::vector<std::vector<uint32_t>> entry;  // per level, per occupied row
    };
    // Appends (self << 32 | slot) to out for every resident of every level
    // (as of the last update) whose box, as the lists hold it, meets the box
    // [lo, hi] (closed intervals on every axis; float bounds): every
    // resident whose exact box meets a box that [lo, hi] holds, and possibly
    // some whose float box only does. Not the oversize bodies (oversize()).
    // Read-only but for the cursors: threads may query at once, each with
    // its own. May throw bad_alloc. (sweep.cpp)
    void query(const float *lo, const float *hi, uint32_t self, QueryCursors &cursors, PairBuffer &out) const;
    // The same residents as query() (closed intervals), each with its box
    // as the lists hold it, appended to out.
    struct QueryBox {
        float lo[3], hi[3];
        uint32_t slot;
    };
    void query_boxes(const float *lo, const float *hi, QueryCursors &cursors, std::vector<QueryBox> &out) const;
    // The oversize bodies of the last update, ascending.
    const std::vector<uint32_t> &oversize() const { return oversize_; }
    // Whether an update has built the grid (false for a new or dropped one).
    bool built() const { return built_; }

    // The slots of every body in the grid, each once, in sweep order: the
    // residents of each level as their lists hold them, then the oversize.
    void order(std::vector<uint32_t> &out) const;
    // Grows the per-slot state to n slots (what renumber() needs for a
    // permutation of n; it may throw bad_alloc, renumber() then does not
    // allocate).
    void reserve_slots(size_t n);
    // Moves the state of slot old_of_new[k] to slot k (a permutation of at
    // least the slot_count slots of the last update, whose slots reserve_slots
    // made room for; new_of_old is its inverse; scratch: kPermuteScratch
    // bytes a slot), on `threads` workers.
    void renumber(const std::vector<uint32_t> &old_of_new, const std::vector<uint32_t> &new_of_old,
                  void *scratch, int threads);
    // Residents whose slot, at the last update, was far from the slot of the
    // resident before them in sweep order among the slots on their side of
    // the split (below): how much memory order the sweep order has lost
    // (order() and renumber() restore it).
    uint64_t disorder() const { return disorder_; }
    // Slots from `split` on form a second run in sweep order of their own
    // (the world stores its static bodies after the others): the disorder
    // then follows each run apart, or every step between them would count.
    void set_split(uint32_t split) { split_ = split; }

    uint32_t level_count() const { return uint32_t(levels_.size()); }
    uint32_t oversize_count() const { return uint32_t(oversize_.size()); }

    // A list's boxes as the sweeps read them (see List).
    struct BoxArrays {
        const float *low_x, *high_x, *low_y, *high_y, *low_z, *high_z;
        const float *reach;  // largest high x so far in the row
        const uint32_t *slot;  // the entry's body
    };

  private:
    friend struct GridTestAccess;  // (tests/support/testing.cpp)
    // An entry with its row key and its low x as the lists hold it
    // (float_box), where entries are sorted before they have box arrays (a
    // list built, entries entering one). Packed: the key is only ever read
    // and written by value.
    struct __attribute__((packed, aligned(8))) Keyed {
        CellKey key;
        uint32_t slot;
        float x;
    };
    struct List {
        // The entries' bodies (slots), sorted by row and within a row by
        // (low x, slot), padded at the end. An entry carries no key: its row
        // is known from the row index below.
        std::vector<uint32_t> slot;
        std::vector<uint32_t> spare;  // what update_lists writes the next slots into
        // Boxes of entries rounded outward to float, same order, as arrays
        // (padded at the end), and the largest high x of the entries of the
        // row up to each (a floor for the sweeps that does not depend on the
        // largest box).
        std::vector<float> low_x, high_x, low_y, high_y, low_z, high_z, reach;
        // The occupied rows: distinct keys in order, and where each row's
        // entries start (one more than rows, ending with count()).
        std::vector<CellKey> row_keys;
        std::vector<uint32_t> row_start;
        size_t count() const { return row_start.empty() ? 0 : row_start.back(); }
        BoxArrays arrays() const {
            return BoxArrays{low_x.data(), high_x.data(), low_y.data(), high_y.data(),
                             low_z.data(), high_z.data(), reach.data(),  slot.data()};
        }
    };
    struct Level {
        int exponent;
        List residents;
        List guests;  // bodies of finer levels, keyed by their row here
        bool queries_finer = false;  // no guests: the residents query the finer levels
    };
    static constexpr int16_t kNone = -1;
    static constexpr int16_t kOversize = -2;

    // What the census finds of a body against the last update (flag, per
    // slot): only changed bodies touch the lists.
    enum Change : uint8_t {
        kSameRow = 0,        // same level and row: every coarser row is the same too
        kNewRow = 1,         // another row of the same level
        kNewMembership = 2,  // new, destroyed, slot reused, or another level
    };
    // A changed body: its slot, and its level and row before. (And its
    // level, row and low x now, taken by the census while the body's point
    // is in cache: looked up afterwards, by slot at random, they cost a
    // cache miss each.)
    struct Moved {
        uint32_t slot;
        int16_t old_level, level;
        float x;  // low x as the lists hold it (float_box)
        int64_t old_cell[2], cell[2];
    };
    struct CensusInput;   // what the census reads (census.cpp)
    struct Census;        // its input and findings
    struct CensusThread;  // what one thread of the census collects
    // The levels a census calls for: (exponent, bodies) ascending, each
    // exponent's level (by exponent + kExponentBias, as level_of_), and
    // which levels keep no guests.
    struct LevelPlan {
        std::vector<std::pair<int, uint64_t>> levels;
        std::vector<int16_t> level_of;
        std::vector<uint8_t> queries_finer;
    };

    // census.cpp: the census of the bodies and what follows from it.
    void take_census(Census &census, int threads, const SlotPass *before);
    void census_slot(const CensusInput &in, CensusThread &mine, int64_t s, RegionGuard &guard);
    int16_t level_index(int exponent) const;
    int exponent_of(const Boxes &boxes, size_t s, int max_exponent) const;
    void enter_all(const Boxes &boxes, const uint32_t *live_gen, uint32_t slot_count, int max_exponent,
                   int threads);
    uint64_t apply_moves(const Census &census, int threads);
    // levels.cpp: the levels from the census's histogram of exponents (a
    // count per exponent and thread).
    LevelPlan plan_levels(const std::vector<uint64_t> &histogram, int threads, const GridLimits &limits) const;
    std::vector<uint8_t> few_bodies(const std::vector<std::pair<int, uint64_t>> &levels) const;

    // lists.cpp: the lists built afresh, or brought to the changed bodies.
    void rebuild(const Boxes &boxes, uint32_t slot_count, int threads);
    CellKey key_of(uint32_t slot, int level_index) const;
    struct ListPart;  // a part of a list's rows that update_lists rewrites
    std::vector<ListPart> plan_list_update(const std::vector<uint8_t> &dirty, const std::vector<Moved> &changed,
                                           std::vector<std::vector<Keyed>> &adds);
    void update_lists(const std::vector<uint8_t> &dirty, const std::vector<uint8_t> &flag,
                      const std::vector<Moved> &changed, int threads);
    // gather.cpp: the box arrays brought to the current boxes; returns the
    // residents' disorder (see disorder()).
    static uint64_t gather(const std::vector<List *> &lists, const Boxes &boxes, uint32_t split, int threads);
    static void sort_row(List &list, size_t begin, size_t end);
    // The residents of level k / 2 for even k, its guests for odd k (the
    // order of all_lists()).
    List &list_at(size_t k) { return (k & 1) ? levels_[k / 2].guests : levels_[k / 2].residents; }
    std::vector<List *> all_lists() {
        std::vector<List *> lists;
        for (size_t k = 0; k < 2 * levels_.size(); ++k) lists.push_back(&list_at(k));
        return lists;
    }
    // sweep.cpp: pairs of the rows [begin, end) of a level's residents (or
    // guests).
    void sweep_residents(const Level &lv, size_t begin, size_t end, PairBuffer &out) const;
    void sweep_guests(const Level &lv, size_t begin, size_t end, PairBuffer &out) const;
    // pairs.cpp: pairs of the box [lo, hi] (body slot) with the residents
    // of levels [0, level_end), by range queries over their rows.
    void query_levels(const double *lo, const double *hi, uint32_t slot, size_t level_end,
                      PairBuffer &out) const;
    void sweep_oversize(const Boxes &boxes, PairBuffer &out) const;
    // sweep.cpp: for query() and query_boxes(), visit(R, rows, row cursor,
    // entry cursors, q) for each level with residents, q the query box as
    // (lo x, hi x, lo y, hi y, lo z, hi z), rows those meeting it.
    template <class Visit>
    void for_each_query_level(const float *lo, const float *hi, QueryCursors &cursors, Visit &&visit) const;

    std::vector<Level> levels_;       // ascending exponent
    std::vector<uint32_t> oversize_;  // slots, ascending
    // Per slot, as of the last update.
    std::vector<int16_t> level_;      // index into levels_, kNone or kOversize
    std::vector<uint32_t> gen_;       // live generation seen
    std::vector<int64_t> cell_;       // 2 per slot: row (y, z) at its own level
    std::vector<int16_t> exponent_;   // level exponent of the box (at least min_exponent), for gen_
    std::vector<float> slack_;        // 2^exponent less 2 r_level, for gen_
    int exponent_floor_ = 0;          // the min_exponent exponent_ was computed with
    std::vector<int16_t> level_of_;   // level index of each exponent (+ kExponentBias), as of the last update
    uint64_t disorder_ = 0;
    uint32_t split_ = UINT32_MAX;  // (set_split)
    bool built_ = false;
};

}  // namespace hgcd
