// shvol report DIR: plots and tables of a batch's ledger, made by tools/report.py.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/ledger.h"

namespace shvol::app {

namespace {

/// The script's process while it runs (0: none yet), and a signal that came before it was known.
std::atomic<pid_t> gScript{0};
std::atomic<int> gEarlySignal{0};
static_assert(std::atomic<pid_t>::is_always_lock_free, "the signal handler reads it");

/// Passes SIGINT, SIGTERM or SIGHUP on to the script, which ends, its temporaries removed, with
/// 128 + the signal.
extern "C" void passToScript(int sig) {
    if (const pid_t pid = gScript.load(); pid > 0)
        ::kill(pid, sig);
    else
        gEarlySignal.store(sig);
}

/// Runs /usr/bin/python3 with `args` and waits for it, passing the signals that would end shvol
/// on to it: std::system ignored SIGINT while it waited (`kill -INT` did nothing), and a SIGTERM
/// ended shvol at once while the script went on and wrote the report a second later (helper
/// 100). The exit status of waitpid.
int runPython(const std::vector<std::string>& args) {
    std::vector<char*> argv = {const_cast<char*>("/usr/bin/python3")};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
    struct sigaction pass {
    }, old[3];
    pass.sa_handler = passToScript;
    sigemptyset(&pass.sa_mask);
    for (int i = 0; i < 3; ++i) {
        ::sigaction(kSignals[i], nullptr, &old[i]);
        if (old[i].sa_handler != SIG_IGN) ::sigaction(kSignals[i], &pass, nullptr);
    }
    // The script starts with the signals blocked and unblocks them once its handlers are in
    // place: a Ctrl-C while Python starts up made it print "Fatal Python error" and a traceback.
    posix_spawnattr_t attr;
    sigset_t held;
    sigemptyset(&held);
    for (const int sig : kSignals) sigaddset(&held, sig);
    posix_spawnattr_init(&attr);
    posix_spawnattr_setsigmask(&attr, &held);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    pid_t pid = 0;
    const int error = ::posix_spawn(&pid, argv[0], nullptr, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    int status = 0;
    if (error == 0) {
        gScript.store(pid);
        if (const int sig = gEarlySignal.exchange(0); sig != 0) ::kill(pid, sig);
        // Waited for without reaping it first, so that its pid cannot be another process's by
        // the time a signal is passed on; then reaped.
        siginfo_t info{};
        while (::waitid(P_PID, id_t(pid), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {
        }
        gScript.store(0);
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
    }
    for (int i = 0; i < 3; ++i) ::sigaction(kSignals[i], &old[i], nullptr);
    // A signal that came once the script had ended is acted on as it would have been without it
    // (the command's own handler, or the default action), not dropped (review).
    if (const int sig = gEarlySignal.exchange(0); sig != 0) std::raise(sig);
    if (error != 0)
        fail("/usr/bin/python3", "",
             "cannot be started (" + std::string(std::strerror(error)) + ")");
    return status;
}

}  // namespace

std::vector<std::string> reportOutputs(const std::vector<std::string>& axes,
                                       const std::vector<std::string>& metrics) {
    // As report.py names them: the error plots when the rows have an error metric, and a time
    // plot for spp and each axis that is a ledger column of its own (not seed: a column
    // beside the axes), every character but an ASCII letter or digit as '_'.
    std::vector<std::string> names = {"report.md", "report.html"};
    for (const char* error : {"rmse", "relmse", "mae"})
        if (std::count(metrics.begin(), metrics.end(), error)) {
            names.insert(names.end(), {"error_vs_time.png", "error_vs_spp.png"});
            break;
        }
    std::vector<std::string> timed;
    const std::set<std::string> beside = ledgerColumnsBesideAxes();
    for (const std::string& a : axes)
        if (!beside.count(a)) timed.push_back(a);
    timed.push_back("spp");
    for (const std::string& a : timed) {
        std::string name = "time_vs_";
        for (const char ch : a) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
        names.push_back(name + ".png");
    }
    return names;
}

int runReport(const std::string& dir, bool quiet) {
    namespace fs = std::filesystem;
    std::error_code ec;  // (what is there first: every case said "no results.jsonl here")
    if (!fs::exists(dir, ec)) fail(dir, "", "no such directory");
    if (!fs::is_directory(dir, ec))
        fail(dir, "", "not a directory (report reads the output directory of shvol batch)");
    if (!fs::exists(fs::path(dir) / "results.jsonl", ec))
        fail(dir, "", "no results.jsonl here: not the output directory of shvol batch");
    const std::string script = sourceTreePath("tools/report.py");
    if (script.empty())
        fail("tools/report.py", "", "not found in the source tree of this shvol program");
    if (!fs::exists("/usr/bin/python3"))
        fail("/usr/bin/python3", "", "not installed (apt-get install python3-matplotlib)");
    std::string columns;  // the ledger's columns that are no axes, for report.py
    for (const std::string& c : ledgerColumnsBesideAxes())
        columns += (columns.empty() ? "" : ",") + c;
    const int status = runPython({script, dir, columns, quiet ? "--quiet" : ""});
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);  // (as the shell reports it)
    if (!WIFEXITED(status))
        fail(script, "", "ended without an exit code (status " + std::to_string(status) + ")");
    return WEXITSTATUS(status);
}

void addReportCommand(CLI::App& app, std::function<int()>& run) {
    auto dir = std::make_shared<std::string>();
    CLI::App* c = app.add_subcommand(
        "report", "Plots and tables (report.md, report.html) of a batch's output directory");
    c->add_option("dir", *dir, "Output directory of shvol batch (with results.jsonl)")
        ->required()
        ->check(nonEmptyName());
    auto quiet = std::make_shared<bool>(false);
    c->add_flag("--quiet", *quiet, "Do not name the files written");
    c->callback([&run, dir, quiet] { run = [dir, quiet] { return runReport(*dir, *quiet); }; });
}

}  // namespace shvol::app
