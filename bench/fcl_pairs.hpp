// FCL's whole pipeline as the benchmarks run it beside hgcd: a broad-phase
// manager's candidate pairs, each handed to fcl::collide (one contact
// wanted); the colliding ones kept as (a << 32 | b), a < b, by the objects'
// user data (the body index). Included only where FCL is (HGCD_BENCH_FCL).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <fcl/narrowphase/collision.h>

struct FclPairs {
    std::vector<uint64_t> pairs;
    uint64_t candidates = 0;

    // The manager's callback (manager.collide(&fcl_pairs, FclPairs::callback)).
    static bool callback(fcl::CollisionObjectd *o1, fcl::CollisionObjectd *o2, void *data) {
        FclPairs *d = static_cast<FclPairs *>(data);
        ++d->candidates;
        fcl::CollisionRequestd request(1, false);
        fcl::CollisionResultd result;
        fcl::collide(o1, o2, request, result);
        if (result.isCollision()) {
            uint64_t a = reinterpret_cast<uintptr_t>(o1->getUserData());
            uint64_t b = reinterpret_cast<uintptr_t>(o2->getUserData());
            if (a > b) std::swap(a, b);
            d->pairs.push_back((a << 32) | b);
        }
        return false;
    }
};
