#pragma once
/// \file A TBB task arena of a given number of worker threads, more than the cores included.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <optional>

namespace shvol {

/// The arena the parallel loops of a command run in: `threads` workers (0: all cores). More
/// threads than cores, as asked, need TBB's limit raised: it keeps its workers to the cores
/// otherwise, printing a warning and running fewer threads.
class ThreadArena {
  public:
    explicit ThreadArena(int threads)
        : threads_(threads > 0 ? threads : tbb::this_task_arena::max_concurrency()) {
        if (threads_ > tbb::this_task_arena::max_concurrency())
            limit_.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads_));
        arena_.initialize(threads_);
    }
    int threads() const { return threads_; }
    template <typename F>
    decltype(auto) execute(F&& f) {
        return arena_.execute(std::forward<F>(f));
    }

  private:
    int threads_;
    std::optional<tbb::global_control> limit_;  // (before the arena: it outlives it)
    tbb::task_arena arena_;  // (initialized in the constructor, once the limit is raised)
};

}  // namespace shvol
