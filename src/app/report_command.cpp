// shvol report DIR: plots and tables of a batch's ledger, made by tools/report.py.
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/ledger.h"

namespace shvol::app {

namespace {

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
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

int runReport(const std::string& dir) {
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
    const int status = std::system(("/usr/bin/python3 " + shellQuote(script) + " " +
                                    shellQuote(dir) + " " + shellQuote(columns))
                                       .c_str());
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) return 130;
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
    c->callback([&run, dir] { run = [dir] { return runReport(*dir); }; });
}

}  // namespace shvol::app
