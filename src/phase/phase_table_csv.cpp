#include "shvol/phase/phase_table_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "shvol/core/error.h"
#include "shvol/core/input_file.h"

namespace shvol {

namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// The whole cell as a decimal number (strtod also accepts "nan" and "inf", and turns 1e999 into
/// inf: the caller rejects them; 1e-320 is the subnormal it is, though strtod sets ERANGE for
/// it). Hexadecimal (0x10), which strtod reads too, is not a number here, as in phase specs.
bool parseNumber(const std::string& cell, double* x) {
    if (cell.empty() || cell.find_first_of("xX") != std::string::npos) return false;
    char* end = nullptr;
    *x = std::strtod(cell.c_str(), &end);
    return end == cell.c_str() + cell.size();
}

std::string str(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

}  // namespace

TabulatedPhase readPhaseTableCsv(const std::string& path) {
    // Only a regular file: /dev/zero or a terminal (tabulated:file=/dev/stdin) would never end.
    const uintmax_t size = regularFileSize(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "", "cannot open phase table");
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // (a read error ends the text early without setting the stream's state: the size tells)
    if (all.size() != size)
        fail(path, "",
             "read error (" + std::to_string(all.size()) + " of " + std::to_string(size) +
                 " bytes read)");
    // A file of another kind: named as such, not as a table whose "header" was its first line
    // and whose second had 1 column (helper 127).
    const std::string notATable =
        ", not a phase table: a tabulated phase function reads CSV text (UTF-8) of (angle in "
        "degrees, value) rows";
    if (const char* kind = fileKindByMagic(all))
        fail(path, "", std::string("the file is ") + kind + notATable);
    if (const size_t nul = all.find('\0'); nul != std::string::npos)
        fail(path, "",
             "a NUL byte at byte " + std::to_string(nul) + " (binary data, or UTF-16 text)" +
                 notATable);
    std::vector<double> angles, values;
    std::string previous;  // the previous row's angle, as written
    std::string text;
    int lineNo = 0;
    bool first = true;
    // Lines end at "\n", "\r\n" or "\r" (classic Mac OS files: read as one line before 6 Dec, a
    // header, and refused as having no rows; helper 103).
    for (size_t pos = 0; pos < all.size();) {
        size_t end = all.find_first_of("\r\n", pos);
        if (end == std::string::npos) end = all.size();
        text = all.substr(pos, end - pos);
        pos = end + (all.compare(end, 2, "\r\n") == 0 ? 2 : 1);
        ++lineNo;
        // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first cell.
        if (lineNo == 1) text.erase(0, utf8BomLength(text));
        const std::string line = trim(text);
        if (line.empty() || line[0] == '#') continue;
        const std::string place = "line " + std::to_string(lineNo);
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) cells.push_back(trim(c));
        if (line.back() == ',') cells.push_back("");
        double angle = 0, value = 0;
        const bool numeric = !cells.empty() && parseNumber(cells[0], &angle);
        // A header line: the first line whose first cell does not even start like a number (a
        // row "0 100" or "0;100" is a malformed row, not a header to drop).
        if (first && !numeric && cells[0].find_first_of("0123456789+-.") != 0) {
            first = false;
            continue;
        }
        first = false;
        if (cells.size() != 2)
            fail(path, place,
                 "expected 2 columns (angle in degrees, value), got " +
                     std::to_string(cells.size()));
        if (!numeric) fail(path, place, "angle \"" + cells[0] + "\" is not a number");
        if (!parseNumber(cells[1], &value))
            fail(path, place, "value \"" + cells[1] + "\" is not a number");
        if (!std::isfinite(angle)) fail(path, place, "angle is not finite");
        if (!std::isfinite(value)) fail(path, place, "value is not finite");
        if (value < 0) fail(path, place, "negative value " + cells[1]);
        if (angle < 0 || angle > 180)
            fail(path, place, "angle " + cells[0] + " outside [0, 180] degrees");
        if (!angles.empty()) {
            if (!(angle > angles.back()))
                fail(path, place,
                     "angle " + cells[0] + " is not greater than the previous angle " + previous +
                         " (angles must increase strictly)");
            // Distinct angles whose cosines round to the same double cannot be interpolated in μ.
            if (std::cos(angle * (Pi / 180)) == std::cos(angles.back() * (Pi / 180)))
                fail(path, place,
                     "angle " + cells[0] + " is too close to the previous angle " + previous +
                         ": their cosines round to the same double, and the table is linear in "
                         "the cosine (near 0° and 180° angles must differ by about 10⁻⁶° or "
                         "more)");
        }
        angles.push_back(angle);
        previous = cells[0];  // (as written: six digits made 179.9999999999 read 180; helper 164)
        values.push_back(value);
    }
    if (lineNo == 0) fail(path, "", "empty file: expected at least 2 (angle, value) rows");
    const std::string end = "line " + std::to_string(lineNo);
    if (angles.size() < 2)
        fail(path, end,
             "expected at least 2 (angle, value) rows, got " + std::to_string(angles.size()));
    // A table running from about 0 to about π is almost surely in radians: read as degrees, it
    // would be a 3° forward peak held constant out to 180°.
    if (angles.front() < 0.1 && angles.back() > 3.0 && angles.back() < Pi + 1e-3)
        fail(path, end,
             "angles run from " + str(angles.front()) + " to " + str(angles.back()) +
                 ", which looks like radians (π = 3.14159); give the angles in degrees, 0 to 180");
    double maxValue = 0;
    for (double v : values) maxValue = std::max(maxValue, v);
    if (!(maxValue > 0)) fail(path, end, "all values are zero");
    // The values are normalised anyway; scaled to a maximum of 1 first, their integral can
    // neither overflow (values near 1e308) nor make the normalisation infinite (values near
    // 1e-320).
    for (double& v : values) v /= maxValue;
    // An end angle whose cosine rounds to ±1 (1e-9° or 179.9999999°) is that end: held constant
    // out to 0° or 180°, it would give two nodes at the same μ.
    if (std::cos(angles.front() * (Pi / 180)) == 1.0) angles.front() = 0;
    if (std::cos(angles.back() * (Pi / 180)) == -1.0) angles.back() = 180;
    try {
        return TabulatedPhase(angles, values, path);
    } catch (const std::invalid_argument& e) {  // a table the checks above should have refused
        fail(path, end, e.what());
    }
}

}  // namespace shvol
