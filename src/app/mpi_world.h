#pragma once
/// \file The processes of one shvol job under mpirun (README.md, "MPI"). MPI is initialised only
/// when the program was started by an MPI launcher (its environment says so) and was built with
/// MPI; otherwise the world is one rank and every call here is a no-op, so a plain run never
/// touches MPI.
#include <functional>
#include <string>
#include <vector>

#include "shvol/core/error.h"
#include "shvol/render/film.h"
#include "shvol/render/renderer.h"

namespace shvol::app {

class MpiWorld {
  public:
    /// The world of this process (one rank until init()).
    static MpiWorld& get();
    /// Joins the MPI job when started by mpirun (call first thing in main); finalize() at exit.
    static void init(int& argc, char**& argv);
    static void finalize();
    /// Whether this process joined an MPI job (started by mpirun, one rank or more).
    static bool launched();
    /// Ends every rank (a rank failed where the others cannot know it).
    [[noreturn]] static void abort(int code);
    /// Whether this program was built with MPI.
    static bool built();

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool root() const { return rank_ == 0; }
    bool parallel() const { return size_ > 1; }
    /// Ranks on this machine (to share its cores between them).
    int localSize() const { return localSize_; }

    /// Collective: the first error message among the ranks ("" when none failed), so a failure
    /// on any rank ends every rank with the same one line instead of leaving the others waiting.
    std::string firstError(const std::string& mine) const;
    /// Collective: returns once every rank has called it.
    void barrier() const;
    /// Collective: rank 0's value of `flag`.
    bool broadcast(bool flag) const;
    /// Collective: adds every rank's sums, counts and sums of squares into rank 0's film, and
    /// its path counters into rank 0's stats. The ranks render disjoint pixels (RenderOptions::
    /// part), so every sum adds exact zeros to the one rank's value: the result does not depend
    /// on the order of the reduction.
    void reduceToRoot(Film& film, RenderStats& stats) const;

    /// Point-to-point text messages (the batch's work queue). recv() waits (sleeping, not
    /// spinning) for a message with `tag` from any rank and names its sender.
    void send(int to, int tag, const std::string& text) const;
    std::string recv(int tag, int& from) const;

  private:
    int rank_ = 0, size_ = 1, localSize_ = 1;
};

/// Runs `setup` on every rank (the part of a command before the ranks split the work): when it
/// throws shvol::Error (or another std::exception, an internal error) on any rank, rank 0 throws
/// the first rank's error as KnownToEveryRank and the others throw ReportedOnRoot. With together
/// = false it only runs `setup` (work of this rank alone).
void collectively(const std::function<void()>& setup, bool together = true);

/// Worker threads for each of `jobs` renders side by side: the machine's cores shared between
/// them and the MPI ranks on this machine, or the cores this rank is bound to where those are
/// fewer (at least 1).
int threadsPerRender(int jobs);
/// Under mpirun, where this rank may run on fewer cores than its share of the machine (OpenMPI
/// binds each rank to one core where it starts at most two; helper 165): that it renders on
/// `threads` threads, and how to avoid it; else "".
std::string bindingWarning(int threads);

/// Thrown on the ranks other than 0 for an error rank 0 reports (main prints nothing for it).
struct ReportedOnRoot {};
/// Thrown on rank 0 for an error after which no other rank waits for it: every rank has met it in
/// collectively(), or the others have all been told to stop (a batch's runs). main reports it and
/// ends normally, as the others do. Any other error ends every rank (MPI_Abort, with OpenMPI's
/// banner): the others may be waiting for this one (a render's film reduced, rank 0's final
/// write can still fail inside a batch's reference, which the others then wait to read).
struct KnownToEveryRank : Error {
    using Error::Error;
};

}  // namespace shvol::app
