#pragma once
/// \file The ledger of a batch: DIR/results.jsonl, one JSON object per finished run, and
/// DIR/results.csv, the same rows as a table (the union of the rows' keys, alphabetical; nested
/// values as JSON text). Both are rewritten whole through a temporary and a rename for every row,
/// so a kill at any moment (kill -9 included) leaves either the old or the new ledger, never half a
/// row.
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"

namespace shvol {

class Ledger {
  public:
    /// Reads DIR/results.jsonl if it exists; a malformed line is an error naming file and line.
    explicit Ledger(std::string dir);
    const std::vector<Json>& rows() const { return rows_; }
    /// The row whose "run" is id, or nullptr.
    const Json* find(const std::string& id) const;
    void append(const Json& row);
    std::string jsonlPath() const;
    std::string csvPath() const;

  private:
    std::string dir_;
    std::vector<Json> rows_;
};

}  // namespace shvol
