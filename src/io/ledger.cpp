#include "shvol/io/ledger.h"

#include <filesystem>
#include <fstream>

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

}  // namespace

Ledger::Ledger(std::string dir) : dir_(std::move(dir)) {
    std::ifstream f(jsonlPath());
    int line = 0;
    for (std::string text; std::getline(f, text);) {
        ++line;
        if (text.empty()) continue;
        try {
            rows_.push_back(Json::parse(text));
        } catch (const Json::exception&) {
            fail(jsonlPath(), "line " + std::to_string(line), "malformed JSON row");
        }
        if (!rows_.back().is_object() || !rows_.back().contains("run"))
            fail(jsonlPath(), "line " + std::to_string(line), "a row without \"run\"");
    }
}

std::string Ledger::jsonlPath() const {
    return (std::filesystem::path(dir_) / "results.jsonl").string();
}
std::string Ledger::csvPath() const {
    return (std::filesystem::path(dir_) / "results.csv").string();
}

const Json* Ledger::find(const std::string& id) const {
    for (const Json& r : rows_)
        if (r["run"] == id) return &r;
    return nullptr;
}

void Ledger::append(const Json& row) {
    rows_.push_back(row);
    std::string jsonl;
    std::vector<std::string> columns;
    for (const Json& r : rows_) {
        jsonl += dumpJson(r) + "\n";
        for (auto it = r.begin(); it != r.end(); ++it)
            if (std::find(columns.begin(), columns.end(), it.key()) == columns.end())
                columns.push_back(it.key());
    }
    std::string csv;
    for (size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + csvField(columns[c]);
    csv += "\n";
    for (const Json& r : rows_) {
        for (size_t c = 0; c < columns.size(); ++c)
            csv += (c ? "," : "") + (r.contains(columns[c]) ? csvField(r[columns[c]]) : "");
        csv += "\n";
    }
    // The CSV first: the JSONL is the record that a run finished.
    writeTextAtomically(csvPath(), csv);
    writeTextAtomically(jsonlPath(), jsonl);
}

}  // namespace shvol
