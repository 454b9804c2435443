#pragma once
// MuJoCo's large allocations kept for reuse (docs/performance.md, "Fixed costs per episode").
//
// Every scene has its own mjModel and so its own state mjData, whose buffer (about 13 MB, most
// of it the constraint arena) and stack (about 41 MB of address space) MuJoCo allocates when the
// data is made and frees with it. Fresh memory costs a page fault per 4 KB page the first time
// it is written, and MuJoCo clears the whole buffer when it makes the data: mj_makeData took
// about 9 ms for co_lift's scene on fresh memory on a 2-core development machine, against 2-3 ms
// on pages already mapped.
//
// keep_large_allocations() installs MuJoCo's allocator hooks (mju_user_malloc, mju_user_free)
// once per process. A block of kLargeBlockBytes or more that MuJoCo frees is kept, up to
// max_kept_blocks() of them (beyond that the oldest goes back to the system), and handed to the
// next allocation it fits: at most an eighth larger, the smallest, the last freed of equals.
// Anything else is allocated and freed as MuJoCo's default allocator does (64-byte aligned, the
// size padded to 64), so memory MuJoCo allocated before the hooks is freed the same way.
// Thread-safe. What MuJoCo computes does not change: it clears a buffer it allocates, and its
// stack holds nothing it has not written.

#include <cstddef>

namespace hribench::sim {

inline constexpr size_t kLargeBlockBytes = size_t{1} << 20;

// Installs the hooks (the first call; later calls do nothing). sim::make_data calls it.
void keep_large_allocations();

// How many freed large blocks are kept at most: four per hardware thread (a worker replacing
// its scene holds the old state's buffer and stack and the new one's at once).
size_t max_kept_blocks();
// How many are kept now, and the bytes they hold.
size_t kept_blocks();
size_t kept_bytes();

}  // namespace hribench::sim
