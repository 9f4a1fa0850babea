#pragma once
/// \file The ledger of a batch: DIR/results.jsonl, one JSON object per finished run, and
/// DIR/results.csv, the same rows as a table (the union of the rows' keys, ordered by
/// ledgerColumnPlace, in order of first appearance; nested values as JSON text). A finished run
/// appends one line to each (the CSV first), with one write call; a row that adds a column rewrites
/// the CSV whole through a temporary and a rename. A kill at any moment (kill -9 included) can
/// leave at most a last JSONL line cut short, which the next Ledger drops (the run renders again; a
/// last line that is a whole row is kept), and a CSV row more than the JSONL holds, which it writes
/// again from the JSONL: no half row survives. A write that fails (a full disk) is cut back off the
/// file, and the ledger then refuses more rows. A Ledger that may write (Open::Repair) holds an
/// exclusive flock(2) on DIR while it lives: a second one, in this process or another, is refused;
/// so is a file naming a run twice.
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "shvol/io/json_reader.h"

namespace shvol {

/// The columns of a batch's ledger row besides the run's axis values and "repeat": those of
/// every run, and those each metric adds. tools/report.py takes the columns that are no axes
/// from `shvol report` (ledgerColumnsBesideAxes), not from a list of its own.
inline const std::set<std::string> kLedgerRunColumns = {"run",
                                                        "seed",
                                                        "spp",
                                                        "wall_time_s",
                                                        "total_s",
                                                        "paths_per_second",
                                                        "image",
                                                        "image_bytes",
                                                        "fingerprint",
                                                        "settings_fingerprint",
                                                        "git_revision",
                                                        "reference_fingerprint"};
inline const std::map<std::string, std::vector<std::string>> kLedgerMetricColumns = {
    {"rmse", {"rmse"}},
    {"relmse", {"relmse"}},
    {"mae", {"mae"}},
    {"bias", {"bias", "bias_ci95"}},
    {"ztest", {"ztest_min_p", "ztest_threshold", "ztest_passed"}}};

/// Every column a ledger row may have that is not an axis: kLedgerRunColumns, every metric's
/// columns and "repeat".
inline std::set<std::string> ledgerColumnsBesideAxes() {
    std::set<std::string> columns = kLedgerRunColumns;
    for (const auto& [metric, added] : kLedgerMetricColumns)
        columns.insert(added.begin(), added.end());
    columns.insert("repeat");
    return columns;
}

/// The place of a column in results.csv: what a row is looked up by first (the run, its repeat,
/// then its axes), then seed and spp, the metrics, the times, and the provenance last. Axes (any
/// column ledgerColumnsBesideAxes does not have) share one place, in order of first appearance.
/// (The columns were in the rows' key order, alphabetical: axes among the metrics; helper 67.)
int ledgerColumnPlace(const std::string& column);
inline constexpr int kLedgerAxisPlace = 2;

class Ledger {
  public:
    /// ReadOnly leaves the files as they are (a last line cut short is only skipped).
    enum class Open { Repair, ReadOnly };
    /// Reads DIR/results.jsonl if it exists; a malformed line is an error naming file and line.
    /// `axes`: the sweep's axes in its order, the order of their columns in results.csv (others
    /// after them, in order of first appearance).
    explicit Ledger(std::string dir, Open open = Open::Repair, std::vector<std::string> axes = {});
    ~Ledger();
    Ledger(const Ledger&) = delete;
    Ledger& operator=(const Ledger&) = delete;
    const std::vector<Json>& rows() const { return rows_; }
    /// The row whose "run" is id, or nullptr.
    const Json* find(const std::string& id) const;
    /// Adds a finished run's row; its "run" must be new. If writing it fails, the row is not
    /// added, the files are left as they were and later appends are refused.
    void append(const Json& row);
    std::string jsonlPath() const;
    std::string csvPath() const;
    /// Whether this ledger holds its directory's lock: no other batch writes there (false where the
    /// file system has no flock, and for Open::ReadOnly).
    bool locked() const { return lock_ >= 0; }

  private:
    /// Reads (and with Open::Repair mends) the files: the constructor's work after the lock.
    void read(Open open);
    /// Adds the row's keys that are not columns yet; true if there were any.
    bool addColumns(const Json& row);
    std::string csvRow(const Json& row) const;
    void writeCsv() const;

    std::string dir_;
    std::vector<std::string> axes_;
    std::vector<Json> rows_;
    std::unordered_map<std::string, size_t> index_;  ///< run id → row
    std::vector<std::string> columns_;  ///< by ledgerColumnPlace, axes_, then first appearance
    std::unordered_set<std::string> columnSet_;
    int lock_ = -1;        ///< DIR, flock'ed (Open::Repair)
    bool failed_ = false;  ///< a write failed: no more rows
};

}  // namespace shvol
