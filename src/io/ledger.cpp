#include "shvol/io/ledger.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"

namespace shvol {

namespace {

std::string csvField(const Json& v) {
    std::string s = v.is_string() ? v.get<std::string>() : dumpJson(v);
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string errnoText(int error = errno) {
    return std::generic_category().message(error);
}

/// Appends text to the file at path (made if missing) with one write(2) call as far as it goes:
/// a kill can cut it short, never interleave it. A write that fails (a full disk, a file size
/// limit) is cut back off, so the file is as it was; the error says if that failed too. The
/// data are flushed (fdatasync) before the file is closed: a network file system may report a
/// full disk or quota only then, and after close the row could no longer be cut back off.
void appendToFile(const std::string& path, const std::string& text) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    struct stat st {};
    if (fd < 0 || ::fstat(fd, &st) != 0) {
        const int error = errno;
        if (fd >= 0) ::close(fd);
        failWriting(path, error);
    }
    auto failCuttingBack = [&](int error, bool written) {
        const bool cutBack = ::ftruncate(fd, st.st_size) == 0;
        ::close(fd);
        if (cutBack || !written) failWriting(path, error);
        fail(path, "", "cannot write file (" + errnoText(error) + "); its last line is cut short");
    };
    for (size_t done = 0; done < text.size();) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) failCuttingBack(n < 0 ? errno : ENOSPC, done > 0);
        done += size_t(n);
    }
    while (::fdatasync(fd) != 0)
        if (errno != EINTR) {
            if (errno == EINVAL) break;  // a file system that cannot sync: the write stands
            failCuttingBack(errno, true);
        }
    if (::close(fd) != 0) failWriting(path, errno);
}

}  // namespace

Ledger::Ledger(std::string dir, Open open, std::vector<std::string> axes)
    : dir_(std::move(dir)), axes_(std::move(axes)) {
    // One writer per directory: two batches appending to one ledger would repeat runs.
    if (open == Open::Repair) {
        lock_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (lock_ < 0) fail(dir_, "", "cannot open the directory (" + errnoText() + ")");
        if (::flock(lock_, LOCK_EX | LOCK_NB) != 0) {
            const int error = errno;
            ::close(lock_);
            lock_ = -1;
            if (error == EWOULDBLOCK)
                fail(dir_, "",
                     "another shvol batch is writing into this directory; wait for it to end or "
                     "use another output directory");
            // A file system without flock (some network ones): the batch goes on unguarded.
            if (error != ENOLCK && error != EOPNOTSUPP && error != ENOSYS)
                fail(dir_, "", "cannot lock the directory (" + errnoText(error) + ")");
            std::fprintf(stderr,
                         "shvol: warning: %s: cannot lock the directory (%s); two batches writing "
                         "into it at once would repeat runs\n",
                         dir_.c_str(), errnoText(error).c_str());
        }
    }
    try {
        read(open);
    } catch (...) {
        if (lock_ >= 0) ::close(lock_);  // (the destructor does not run: the lock would stay)
        throw;
    }
}

void Ledger::read(Open open) {
    std::string text;
    {
        std::ifstream f(jsonlPath(), std::ios::binary);
        std::stringstream ss;
        ss << f.rdbuf();
        text = ss.str();
    }
    const size_t original = text.size();
    // Rows end in '\n': a last line without it is a row a kill cut short while it was appended.
    // It is dropped (its run renders again) and the file rewritten without it.
    size_t whole = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
    // ... unless it is a whole row (a hand-edited file without a final newline): then kept, and
    // given its newline.
    if (whole < text.size()) {
        const Json last = Json::parse(text.substr(whole), nullptr, false);
        if (last.is_object() && last.contains("run") && last["run"].is_string())
            text += '\n', whole = text.size();
    }
    std::istringstream lines(text.substr(0, whole));
    int line = 0;
    std::vector<int> lineOf;  // row → its line
    for (std::string row; std::getline(lines, row);) {
        ++line;
        if (row.find_first_not_of(" \t\r") == std::string::npos) continue;
        // (A row nested deeper than any the batch writes is refused before it is built: its
        // recursive walks would overflow the stack, as a scene's did; json_reader.h.)
        const auto tooDeep = [&] {
            fail(jsonlPath(), "line " + std::to_string(line), tooDeepMessage());
        };
        try {
            rows_.push_back(parseWithinDepth(row, tooDeep));
        } catch (const Json::exception&) {
            fail(jsonlPath(), "line " + std::to_string(line), "malformed JSON row");
        }
        if (!rows_.back().is_object() || !rows_.back().contains("run") ||
            !rows_.back()["run"].is_string())
            fail(jsonlPath(), "line " + std::to_string(line), "a row without \"run\"");
        // (the batch compares these with its own; read as strings)
        for (const char* key :
             {"fingerprint", "settings_fingerprint", "git_revision", "reference_fingerprint"})
            if (rows_.back().contains(key) && !rows_.back()[key].is_string())
                fail(jsonlPath(), "line " + std::to_string(line),
                     std::string("\"") + key + "\" is not a string");
        const std::string id = rows_.back()["run"].get<std::string>();
        lineOf.push_back(line);
        if (const auto [it, added] = index_.emplace(id, rows_.size() - 1); !added)
            fail(jsonlPath(), "line " + std::to_string(line),
                 "run " + id + " again (first at line " + std::to_string(lineOf[it->second]) +
                     "): two batches wrote into this directory; delete one of the two lines, or "
                     "use another output directory");
        addColumns(rows_.back());
    }
    if (open == Open::ReadOnly) return;
    if (whole != original) writeTextAtomically(jsonlPath(), text.substr(0, whole));
    // The CSV may hold a row the JSONL does not (a kill between the two appends): made again.
    if (!rows_.empty()) writeCsv();
}

Ledger::~Ledger() {
    if (lock_ >= 0) ::close(lock_);  // (which releases the lock)
}

std::string Ledger::jsonlPath() const {
    return (std::filesystem::path(dir_) / "results.jsonl").string();
}
std::string Ledger::csvPath() const {
    return (std::filesystem::path(dir_) / "results.csv").string();
}

const Json* Ledger::find(const std::string& id) const {
    const auto it = index_.find(id);
    return it == index_.end() ? nullptr : &rows_[it->second];
}

int ledgerColumnPlace(const std::string& column) {
    if (column == "run") return 0;
    if (column == "repeat") return 1;
    if (column == "seed" || column == "spp") return 3;
    // The metrics in the order README lists them, each's columns in their order.
    int place = 4;
    for (const char* metric : {"rmse", "relmse", "mae", "bias", "ztest"})
        for (const std::string& c : kLedgerMetricColumns.at(metric)) {
            ++place;
            if (c == column) return place;
        }
    for (const char* time : {"wall_time_s", "total_s", "paths_per_second"}) {
        ++place;
        if (column == time) return place;
    }
    // The provenance (image, fingerprints, revision), then; any other column is an axis.
    return kLedgerRunColumns.count(column) ? place + 1 : kLedgerAxisPlace;
}

bool Ledger::addColumns(const Json& row) {
    bool added = false;
    for (auto it = row.begin(); it != row.end(); ++it)
        if (columnSet_.insert(it.key()).second) columns_.push_back(it.key()), added = true;
    // Axes in the sweep's order (a row's keys come alphabetically: helper 77 found the CSV's
    // axes sorted, not in the order the experiment lists them).
    const auto place = [&](const std::string& c) {
        const int p = ledgerColumnPlace(c);
        if (p != kLedgerAxisPlace) return std::pair<int, size_t>(p, 0);
        return std::pair<int, size_t>(
            p, size_t(std::find(axes_.begin(), axes_.end(), c) - axes_.begin()));
    };
    if (added)
        std::stable_sort(columns_.begin(), columns_.end(),
                         [&](const auto& a, const auto& b) { return place(a) < place(b); });
    return added;
}

std::string Ledger::csvRow(const Json& row) const {
    std::string line;
    for (size_t c = 0; c < columns_.size(); ++c)
        line += (c ? "," : "") + (row.contains(columns_[c]) ? csvField(row[columns_[c]]) : "");
    return line + "\n";
}

void Ledger::writeCsv() const {
    std::string csv;
    for (size_t c = 0; c < columns_.size(); ++c) csv += (c ? "," : "") + csvField(columns_[c]);
    csv += "\n";
    for (const Json& r : rows_) csv += csvRow(r);
    writeTextAtomically(csvPath(), csv);
}

void Ledger::append(const Json& row) {
    const std::string id = row.value("run", "");
    if (id.empty() || find(id)) fail(jsonlPath(), "run " + id, "a row without a new \"run\"");
    if (failed_) fail(jsonlPath(), "run " + id, "not added: an earlier write to the ledger failed");
    rows_.push_back(row);
    index_.emplace(id, rows_.size() - 1);
    // The CSV first: the JSONL is the record that a run finished. A row with a new column (the
    // first rows, mostly) rewrites the table; the others add one line to each file, so a batch
    // of n runs writes O(n) bytes, not O(n²). A failed write leaves the row out of both files
    // (the CSV is cut back or rewritten as it was; were that to fail too, the next open makes
    // it again from the JSONL) and the ledger refuses more rows.
    const std::vector<std::string> columnsBefore = columns_;
    std::error_code ec;
    const uintmax_t csvBefore = std::filesystem::file_size(csvPath(), ec);
    const bool csvExisted = !ec;
    enum { None, Appended, Rewritten } csv = None;
    try {
        if (addColumns(row) || rows_.size() == 1)
            writeCsv(), csv = Rewritten;
        else
            appendToFile(csvPath(), csvRow(row)), csv = Appended;
        appendToFile(jsonlPath(), dumpJson(row) + "\n");
    } catch (...) {
        failed_ = true;
        index_.erase(id);
        rows_.pop_back();
        // (New columns are sorted among the old ones, not only appended: review.)
        columns_ = columnsBefore;
        columnSet_ = std::unordered_set<std::string>(columns_.begin(), columns_.end());
        try {
            if (!csvExisted && csv != None) std::filesystem::remove(csvPath());
            if (csvExisted && csv == Appended) std::filesystem::resize_file(csvPath(), csvBefore);
            if (csvExisted && csv == Rewritten) writeCsv();
        } catch (...) {  // (the error to report is the first)
        }
        throw;
    }
}

}  // namespace shvol
