#include "sim/memory.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

#include <mujoco/mujoco.h>

namespace hribench::sim {
namespace {

constexpr size_t kAlignment = 64;  // as mju_malloc's default

struct Block {
  void* data = nullptr;
  size_t bytes = 0;
};

struct Blocks {
  std::mutex mutex;
  std::vector<Block> handed_out;  // large blocks MuJoCo holds
  std::vector<Block> kept;        // large blocks freed, oldest first
};

Blocks& blocks() {
  static Blocks* b = new Blocks;  // never destroyed: MuJoCo may free after static destructors
  return *b;
}

void* allocate(size_t size) {
  const size_t bytes = std::max<size_t>((size + kAlignment - 1) / kAlignment * kAlignment, kAlignment);
  if (bytes < kLargeBlockBytes) return std::aligned_alloc(kAlignment, bytes);
  Blocks& b = blocks();
  {
    const std::lock_guard<std::mutex> lock(b.mutex);
    // The smallest kept block that holds it, no more than an eighth larger; of equal ones the
    // last freed (its pages the likeliest still in a cache).
    auto best = b.kept.end();
    for (auto it = b.kept.begin(); it != b.kept.end(); ++it) {
      if (it->bytes >= bytes && it->bytes - bytes <= bytes / 8 && (best == b.kept.end() || it->bytes <= best->bytes)) {
        best = it;
      }
    }
    if (best != b.kept.end()) {
      const Block block = *best;
      b.kept.erase(best);
      b.handed_out.push_back(block);
      return block.data;
    }
  }
  void* data = std::aligned_alloc(kAlignment, bytes);
  if (data == nullptr) return nullptr;  // mju_malloc reports it
  const std::lock_guard<std::mutex> lock(b.mutex);
  b.handed_out.push_back({data, bytes});
  return data;
}

void release(void* data) {
  if (data == nullptr) return;
  Blocks& b = blocks();
  void* evicted = data;
  {
    const std::lock_guard<std::mutex> lock(b.mutex);
    const auto it = std::find_if(b.handed_out.begin(), b.handed_out.end(),
                                 [data](const Block& block) { return block.data == data; });
    if (it != b.handed_out.end()) {
      b.kept.push_back(*it);
      b.handed_out.erase(it);
      evicted = nullptr;
      if (b.kept.size() > max_kept_blocks()) {
        evicted = b.kept.front().data;
        b.kept.erase(b.kept.begin());
      }
    }
  }
  std::free(evicted);  // a small block, one allocated before the hooks, or the oldest kept
}

}  // namespace

void keep_large_allocations() {
  static std::once_flag once;
  std::call_once(once, [] {
    blocks();
    mju_user_malloc = allocate;
    mju_user_free = release;
  });
}

size_t max_kept_blocks() {
  return 4 * std::max<size_t>(1, std::thread::hardware_concurrency());
}

size_t kept_blocks() {
  const std::lock_guard<std::mutex> lock(blocks().mutex);
  return blocks().kept.size();
}

size_t kept_bytes() {
  const std::lock_guard<std::mutex> lock(blocks().mutex);
  size_t n = 0;
  for (const Block& block : blocks().kept) n += block.bytes;
  return n;
}

}  // namespace hribench::sim
