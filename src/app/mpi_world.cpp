#include "mpi_world.h"

#include <sched.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <type_traits>

#include "commands.h"
#include "shvol/core/error.h"

#ifdef SHVOL_HAVE_MPI
#include <mpi.h>
#endif

namespace shvol::app {

MpiWorld& MpiWorld::get() {
    static MpiWorld world;
    return world;
}

bool MpiWorld::built() {
#ifdef SHVOL_HAVE_MPI
    return true;
#else
    return false;
#endif
}

#ifdef SHVOL_HAVE_MPI

namespace {

/// Started by an MPI launcher (OpenMPI's mpirun sets OMPI_COMM_WORLD_SIZE; PMIx and PMI
/// launchers set PMIX_RANK or PMI_SIZE).
bool launchedByMpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
        if (std::getenv(v)) return true;
    return false;
}

bool gInitialised = false;

// PathCounters is a run of uint64_t counters (TrackingCounters included), reduced as one array
// (the spread of the image, a double, is recomputed from the reduced film: helper 87 found doubles
// summed as integers; it was a counter then). A counter of another type needs its own reduction.
constexpr int kCounterWords = int(sizeof(PathCounters) / sizeof(uint64_t));
static_assert(kCounterWords == 16 + 5 + 3 + PhaseWeightMoments::kBins &&
                  std::is_same_v<decltype(PathCounters::paths), uint64_t> &&
                  std::is_same_v<decltype(PhaseWeightMoments::paths)::value_type, uint64_t>,
              "PathCounters: its 16 uint64_t counters, InvalidDraws' 5, TrackingCounters' 3 and "
              "PhaseWeightMoments' bins; a field added there must be reduced here (as an "
              "integer only if it is one)");

template <typename T>
void reduce(std::vector<T>& v, MPI_Datatype type, bool root, MPI_Op op = MPI_SUM) {
    if (v.empty()) return;
    if (root)
        MPI_Reduce(MPI_IN_PLACE, v.data(), int(v.size()), type, op, 0, MPI_COMM_WORLD);
    else
        MPI_Reduce(v.data(), nullptr, int(v.size()), type, op, 0, MPI_COMM_WORLD);
}

}  // namespace

void MpiWorld::init(int& argc, char**& argv) {
    if (!launchedByMpi()) return;
    int provided = 0;
    // The batch's rank 0 serves the queue from a thread while its main thread renders.
    MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &provided);
    gInitialised = true;
    MpiWorld& w = get();
    MPI_Comm_rank(MPI_COMM_WORLD, &w.rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &w.size_);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
    MPI_Comm_size(local, &w.localSize_);
    MPI_Comm_free(&local);
    if (w.size_ > 1 && provided < MPI_THREAD_MULTIPLE && w.rank_ == 0)
        std::fprintf(stderr,
                     "shvol: warning: the MPI library gives no MPI_THREAD_MULTIPLE; "
                     "shvol batch needs it with several ranks\n");
}

bool MpiWorld::launched() {
    return gInitialised;
}

void MpiWorld::finalize() {
    if (gInitialised) MPI_Finalize();
    gInitialised = false;
}

void MpiWorld::abort(int code) {
    if (gInitialised) MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
}

std::string MpiWorld::firstError(const std::string& mine) const {
    if (!parallel()) return mine;
    const int candidate = mine.empty() ? size_ : rank_;
    int first = size_;
    MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == size_) return "";
    int length = int(mine.size());
    MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
    std::string text = mine;
    text.resize(size_t(length));
    MPI_Bcast(text.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
    return text;
}

void MpiWorld::barrier() const {
    if (parallel()) MPI_Barrier(MPI_COMM_WORLD);
}

bool MpiWorld::broadcast(bool flag) const {
    if (!parallel()) return flag;
    int v = flag;
    MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return v != 0;
}

void MpiWorld::reduceToRoot(Film& film, RenderStats& stats) const {
    if (!parallel()) return;
    reduce(film.sum, MPI_DOUBLE, root());
    reduce(film.count, MPI_UINT32_T, root());
    reduce(film.sumSq, MPI_DOUBLE, root());
    reduce(film.luminanceSumSq, MPI_DOUBLE, root());
    std::vector<uint64_t> c(kCounterWords);
    std::memcpy(c.data(), &stats.counters, sizeof(PathCounters));
    reduce(c, MPI_UINT64_T, root());
    std::vector<double> wall{stats.wallSeconds};  // the slowest rank's
    reduce(wall, MPI_DOUBLE, root(), MPI_MAX);
    if (!root()) return;
    std::memcpy(&stats.counters, c.data(), sizeof(PathCounters));
    // From the whole film, in pixel order: the one process's value, bit for bit.
    stats.imageMeanRelativeError = film.meanRelativeError();
    stats.imageMeanRelativeErrorDof = film.meanRelativeErrorDof();
    stats.wallSeconds = wall[0];
    stats.minSamples = film.minCount();
    stats.maxSamples = film.maxCount();
}

void MpiWorld::send(int to, int tag, const std::string& text) const {
    MPI_Send(text.data(), int(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

std::string MpiWorld::recv(int tag, int& from) const {
    MPI_Status status;
    MPI_Message message;
    // OpenMPI's blocking probe spins a core; rank 0 waits for requests beside its own render, so
    // it polls and sleeps instead (a millisecond of latency per run is nothing).
    for (int found = 0;;) {
        MPI_Improbe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &found, &message, &status);
        if (found) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    std::string text(size_t(length), '\0');
    MPI_Mrecv(text.data(), length, MPI_CHAR, &message, &status);
    from = status.MPI_SOURCE;
    return text;
}

#else  // built without MPI: one rank

void MpiWorld::init(int&, char**&) {}
bool MpiWorld::launched() {
    return false;
}
void MpiWorld::finalize() {}
void MpiWorld::abort(int code) {
    std::exit(code);
}
std::string MpiWorld::firstError(const std::string& mine) const {
    return mine;
}
void MpiWorld::barrier() const {}
bool MpiWorld::broadcast(bool flag) const {
    return flag;
}
void MpiWorld::reduceToRoot(Film&, RenderStats&) const {}
void MpiWorld::send(int, int, const std::string&) const {}
std::string MpiWorld::recv(int, int& from) const {
    from = 0;
    return "";
}

#endif

void collectively(const std::function<void()>& setup, bool together) {
    if (!together || !MpiWorld::get().parallel()) return setup();
    std::string error;
    try {
        setup();
    } catch (const std::exception& e) {  // any: the other ranks must not wait forever
        error = errorMessage(e);
    }
    error = MpiWorld::get().firstError(error);
    if (error.empty()) return;
    if (MpiWorld::get().root()) throw KnownToEveryRank(error);
    throw ReportedOnRoot{};
}

namespace {
/// The machine's cores, and those this process may run on (its CPU affinity: mpirun binds each
/// rank to one core where it starts at most two, OpenMPI 4.1), at most the machine's.
int machineCores() {
    return int(std::max(1u, std::thread::hardware_concurrency()));
}
int allowedCores() {
    // (A set sized for the CPUs configured: a fixed cpu_set_t holds 1024, and on machines of more
    // sched_getaffinity fails; review.)
    const int cpus = std::max<int>(CPU_SETSIZE, int(sysconf(_SC_NPROCESSORS_CONF)));
    cpu_set_t* set = CPU_ALLOC(cpus);
    const size_t size = CPU_ALLOC_SIZE(cpus);
    CPU_ZERO_S(size, set);
    const int allowed = sched_getaffinity(0, size, set) == 0 ? CPU_COUNT_S(size, set) : 0;
    CPU_FREE(set);
    return allowed > 0 ? std::min(allowed, machineCores()) : machineCores();
}
/// The cores a rank's renders share: its part of the machine's, or the cores it is bound to
/// where those are fewer (threads beyond them would share them: a bound rank of a batch
/// rendered on two threads on one core; helper 165).
int rankCores() {
    return std::min(allowedCores(), machineCores() / std::max(1, MpiWorld::get().localSize()));
}
}  // namespace

int threadsPerRender(int jobs) {
    return std::max(1, rankCores() / std::max(1, jobs));
}

std::string bindingWarning(int threads) {
    const int cores = machineCores(), ranks = std::max(1, MpiWorld::get().localSize());
    if (!MpiWorld::launched()) return "";
    const int allowed = allowedCores();
    if (allowed >= cores / ranks) return "";
    // (Its affinity, not mpirun's binding alone: taskset or a container's cpuset narrow it too,
    // where --bind-to none changes nothing; review.)
    return "this rank may run on " + std::to_string(allowed) + " of the machine's " +
           std::to_string(cores) + " cores (its CPU affinity; " + std::to_string(ranks) + " rank" +
           (ranks == 1 ? "" : "s") + " on the machine): it renders on " + std::to_string(threads) +
           (threads == 1 ? " thread" : " threads") +
           " unless --threads says otherwise; where mpirun bound it (OpenMPI binds each rank to "
           "one core where it starts at most two), `mpirun --bind-to none` gives each rank its "
           "share, " +
           std::to_string(std::max(1, cores / ranks)) + " cores";
}

}  // namespace shvol::app
