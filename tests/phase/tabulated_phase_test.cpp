#include "shvol/phase/tabulated_phase.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>

#include "phase/phase_test_util.h"
#include "shvol/core/error.h"
#include "shvol/phase/henyey_greenstein.h"
#include "shvol/phase/phase_table_csv.h"

namespace shvol {
namespace {

using testing::checkFiniteAtExtremes;
using testing::checkSamples;
using testing::evalIntegral;
using testing::phaseChi2;

const std::string kMieLike = std::string(SHVOL_SOURCE_DIR) + "/media/phase/mie_like.csv";

/// HG(g) tabulated at every `step` degrees from 0 to 180.
TabulatedPhase hgTable(double g, double step = 1.0) {
    std::vector<double> a, v;
    for (double d = 0; d <= 180 + 1e-9; d += step) {
        a.push_back(d);
        v.push_back(henyeyGreenstein(std::cos(d * Pi / 180), g));
    }
    return TabulatedPhase(a, v, "hg table");
}

TEST(Tabulated, ReproducesHgFromOneDegreeTable) {
    const TabulatedPhase t = hgTable(0.5);
    // HG is normalised, so the factor is 1 up to the trapezoid error of the integral in μ:
    // with spacing h = sin θ · Δθ (Δθ = 1° = 0.01745) and p''/p = 15g²/b², b = 1 + g² − 2gμ,
    // the relative error is at most Δθ²/12 · max (1 − μ²) 15g²/b² = 2.54e-5 · 6.7 = 1.7e-4
    // (the maximum is at μ ≈ 0.8 for g = 0.5).
    EXPECT_NEAR(t.normalization(), 1.0, 1.7e-4);
    double maxRel = 0;
    for (int i = 0; i <= 100000; ++i) {
        const double mu = -1 + 2 * i / 100000.0;
        maxRel = std::max(maxRel, std::abs(t.evalCos(mu) / henyeyGreenstein(mu, 0.5) - 1));
    }
    // Linear interpolation errs by at most h²/8 · p''/p = Δθ²/8 · (1 − μ²) 15g²/b² ≤
    // 3.8e-5 · 6.7 = 2.5e-4, plus the normalisation's 1.7e-4 (bounds as above).
    EXPECT_LT(maxRel, 2.5e-4 + 1.7e-4);
    std::cout << "[ measured ] HG(0.5) 1-degree table: max relative error " << maxRel
              << ", normalization factor " << t.normalization() << "\n";
}

TEST(Tabulated, PdfEqualsEvalAndNormalised) {
    const TabulatedPhase t = readPhaseTableCsv(kMieLike);
    EXPECT_NEAR(evalIntegral(t), 1.0, 1e-7);
    checkSamples(t, true, 1e-9, 2000);
    checkSamples(hgTable(0.9), true, 1e-9, 2000);
    checkFiniteAtExtremes(t);
    checkFiniteAtExtremes(hgTable(0.999999, 0.5));
    EXPECT_EQ(PhaseFunction(t).name(), "tabulated");
    std::cout << "[ measured ] mie_like.csv normalization factor " << t.normalization() << "\n";
}

TEST(Tabulated, SamplerInvertsCdf) {
    const TabulatedPhase t = readPhaseTableCsv(kMieLike);
    for (double u : {0.0, 1e-9, 0.01, 0.2, 0.5, 0.8, 0.97, 1 - 1e-9, 1.0}) {
        const double mu = t.sample(Vec3(0, 0, 1), Vec2(u, 0.0)).wi.z();
        EXPECT_NEAR(t.table().cdf(mu), u, 1e-12) << u;
    }
}

TEST(Tabulated, ConstantTableIsIsotropicAndPartialTablesExtend) {
    const TabulatedPhase iso({0, 180}, {7, 7});
    EXPECT_NEAR(iso.evalCos(0.3), Inv4Pi, 1e-16);
    EXPECT_NEAR(iso.normalization(), 1 / (7 * FourPi), 1e-16);
    // 30°…150° only: values held constant towards 0° and 180°.
    const TabulatedPhase part({30, 90, 150}, {2, 1, 3});
    EXPECT_DOUBLE_EQ(part.evalCos(1.0), part.evalCos(std::cos(Pi / 6)));
    EXPECT_DOUBLE_EQ(part.evalCos(0.95), part.evalCos(1.0));
    EXPECT_DOUBLE_EQ(part.evalCos(-1.0), 3 * part.normalization());
    EXPECT_NEAR(evalIntegral(part), 1.0, 1e-7);
}

class TabulatedChi2 : public ::testing::TestWithParam<int> {};

TEST_P(TabulatedChi2, SamplerMatchesPdf) {
    const TabulatedPhase t = GetParam() == 0   ? readPhaseTableCsv(kMieLike)
                             : GetParam() == 1 ? hgTable(0.5)
                                               : hgTable(-0.95, 0.25);
    const auto r = phaseChi2(t, 3, 900 + GetParam());
    EXPECT_TRUE(r.passed) << GetParam() << "\n" << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Tabulated, TabulatedChi2, ::testing::Values(0, 1, 2));

// ---- CSV errors -------------------------------------------------------------------------------

std::string writeCsv(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << text;
    return path;
}

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(TabulatedCsv, ReadsHeaderCommentsAndBlankLines) {
    const std::string p = writeCsv("ok.csv", "# made up\nangle, value\n\n0, 2\n 90 ,1\r\n180,2\n");
    const TabulatedPhase t = readPhaseTableCsv(p);
    EXPECT_EQ(t.source(), p);
    EXPECT_EQ(t.table().nodes().size(), 3u);
    EXPECT_DOUBLE_EQ(t.evalCos(1.0) / t.evalCos(0.0), 2.0);
}

TEST(TabulatedCsv, OneLineErrors) {
    const auto err = [](const std::string& name, const std::string& text) {
        const std::string p = writeCsv(name, text);
        const std::string m = messageOf([&] { readPhaseTableCsv(p); });
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        EXPECT_EQ(m.rfind(p + ": ", 0), 0u) << m;
        return m.substr(p.size() + 2);
    };
    EXPECT_EQ(messageOf([] { readPhaseTableCsv("/nonexistent/dir/mie.csv"); }),
              "/nonexistent/dir/mie.csv: no such file");
    EXPECT_EQ(err("nonnum.csv", "angle,value\n0,1\n10,abc\n"),
              "line 3: value \"abc\" is not a number");
    EXPECT_EQ(err("nonnum_angle.csv", "0,1\nten,1\n"), "line 2: angle \"ten\" is not a number");
    // Hexadecimal, which strtod reads, is refused as in phase specs (it was read; helper 55).
    EXPECT_EQ(err("hex.csv", "0,1\n90,0x10\n180,1\n"), "line 2: value \"0x10\" is not a number");
    EXPECT_EQ(err("hexangle.csv", "0,1\n0xB4,1\n"), "line 2: angle \"0xB4\" is not a number");
    EXPECT_EQ(err("neg.csv", "0,1\n# c\n90,-0.5\n180,1\n"), "line 3: negative value -0.5");
    EXPECT_EQ(err("nan.csv", "0,1\n90,nan\n180,1\n"), "line 2: value is not finite");
    EXPECT_EQ(err("order.csv", "0,1\n90,1\n90,2\n180,1\n"),
              "line 3: angle 90 is not greater than the previous angle 90 (angles must increase "
              "strictly)");
    EXPECT_EQ(err("decr.csv", "0,1\n90,1\n45,2\n"),
              "line 3: angle 45 is not greater than the previous angle 90 (angles must increase "
              "strictly)");
    // (why it is too close, and by how much: helper 94 found the bare "too close" unclear)
    EXPECT_EQ(err("close.csv", "0,1\n1e-9,2\n180,1\n"),
              "line 2: angle 1e-9 is too close to the previous angle 0: their cosines round to "
              "the same double, and the table is linear in the cosine (near 0° and 180° angles "
              "must differ by about 10⁻⁶° or more)");
    // The previous angle as written (six digits made it read as the angle itself; helper 164).
    EXPECT_EQ(err("close180.csv", "0,1\n179.9999999999,2\n180,1\n"),
              "line 3: angle 180 is too close to the previous angle 179.9999999999: their cosines "
              "round to the same double, and the table is linear in the cosine (near 0° and 180° "
              "angles must differ by about 10⁻⁶° or more)");
    EXPECT_EQ(err("order2.csv", "0,1\n90.0000001,1\n90,2\n180,1\n"),
              "line 3: angle 90 is not greater than the previous angle 90.0000001 (angles must "
              "increase strictly)");
    EXPECT_EQ(err("one.csv", "angle,value\n0,1\n"),
              "line 2: expected at least 2 (angle, value) rows, got 1");
    // (an empty file has no line to name: it was "line 0"; helper 84)
    EXPECT_EQ(err("empty.csv", ""), "empty file: expected at least 2 (angle, value) rows");
    EXPECT_EQ(err("cols.csv", "0,1\n90,1,5\n"),
              "line 2: expected 2 columns (angle in degrees, value), got 3");
    EXPECT_EQ(err("emptycell.csv", "0,1\n90,\n"), "line 2: value \"\" is not a number");
    EXPECT_EQ(err("range.csv", "0,1\n190,1\n"), "line 2: angle 190 outside [0, 180] degrees");
    EXPECT_EQ(err("zero.csv", "0,0\n180,0\n"), "line 2: all values are zero");
    EXPECT_EQ(err("header2.csv", "angle,value\n0,1\nangle,value\n"),
              "line 3: angle \"angle\" is not a number");
    EXPECT_EQ(err("radians.csv", "0,5\n1.5708,1\n3.14159,2\n"),
              "line 3: angles run from 0 to 3.14159, which looks like radians (π = 3.14159); give "
              "the angles in degrees, 0 to 180");
    // A first row with another separator is a malformed row, not a header to drop.
    EXPECT_EQ(err("space.csv", "0 100\n10,1\n180,1\n"),
              "line 1: expected 2 columns (angle in degrees, value), got 1");
    EXPECT_EQ(err("semicolon.csv", "0;100\n10;1\n"),
              "line 1: expected 2 columns (angle in degrees, value), got 1");
    EXPECT_EQ(err("radians2.csv", "0,1\n3.14159,1\n"),
              "line 2: angles run from 0 to 3.14159, which looks like radians (π = 3.14159); give "
              "the angles in degrees, 0 to 180");
    EXPECT_EQ(err("huge.csv", "0,1\n90,1e999\n180,1\n"), "line 2: value is not finite");
    // Files of another kind (they read as a header line, then a row of 1 column; helper 127).
    const std::string rows =
        ", not a phase table: a tabulated phase function reads CSV text (UTF-8) of (angle in "
        "degrees, value) rows";
    EXPECT_EQ(err("sky.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0channels\0", 16)),
              "the file is an OpenEXR image" + rows);
    EXPECT_EQ(err("cloud.vdb", std::string(" BDV\0\0\0\0\xda\0", 10)),
              "the file is an OpenVDB grid" + rows);
    EXPECT_EQ(err("mesh.ply", "ply\r\nformat ascii 1.0\r\n"), "the file is a PLY mesh" + rows);
    EXPECT_EQ(err("image.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)),
              "the file is a PNG image" + rows);
    EXPECT_EQ(err("data.bin", std::string("\x89PNX\r\n\x1a\n\0\0\0\rIHDR", 16)),
              "a NUL byte at byte 8 (binary data, or UTF-16 text)" + rows);
    // A short table in degrees that ends before π is still fine.
    EXPECT_EQ(messageOf([&] { readPhaseTableCsv(writeCsv("peak.csv", "0,5\n1,2\n2.5,1\n")); }),
              "(no error)");
}

// A UTF-8 byte-order mark before the first row (spreadsheets write one) is not part of it: the
// row was taken for a header and dropped, and the forward peak with it.
TEST(TabulatedCsv, ByteOrderMark) {
    const TabulatedPhase plain = readPhaseTableCsv(writeCsv("plain.csv", "0,100\n10,1\n180,1\n"));
    const TabulatedPhase bom = readPhaseTableCsv(writeCsv("bom.csv",
                                                          "\xEF\xBB\xBF"
                                                          "0,100\n10,1\n180,1\n"));
    EXPECT_EQ(bom.table().nodes().size(), plain.table().nodes().size());
    EXPECT_DOUBLE_EQ(bom.evalCos(1.0), plain.evalCos(1.0));
    const TabulatedPhase header = readPhaseTableCsv(writeCsv("bomheader.csv",
                                                             "\xEF\xBB\xBF"
                                                             "angle,value\n0,100\n10,1\n180,1\n"));
    EXPECT_DOUBLE_EQ(header.evalCos(1.0), plain.evalCos(1.0));
}

// Lines end at "\n", "\r\n" or "\r" alike (a classic Mac OS file, "\r" only, was one line: taken
// for a header and refused as "expected at least 2 (angle, value) rows, got 0"; helper 103), and
// an error names the line as the file has it.
TEST(TabulatedCsv, LineEndings) {
    const TabulatedPhase plain =
        readPhaseTableCsv(writeCsv("lf.csv", "angle,value\n0,10\n90,1\n180,2\n"));
    for (const char* text :
         {"angle,value\r0,10\r90,1\r180,2\r", "angle,value\r\n0,10\r\n90,1\r\n180,2"}) {
        const TabulatedPhase t = readPhaseTableCsv(writeCsv("cr.csv", text));
        EXPECT_EQ(t.table().nodes().size(), plain.table().nodes().size()) << text;
        for (const double mu : {1.0, 0.3, -1.0}) EXPECT_DOUBLE_EQ(t.evalCos(mu), plain.evalCos(mu));
    }
    const std::string p = writeCsv("crbad.csv", "angle,value\r0,10\r\n90,x\r180,2\r");
    EXPECT_EQ(messageOf([&] { readPhaseTableCsv(p); }),
              p + ": line 3: value \"x\" is not a number");
}

// Found by fuzz/phase_csv_fuzzer: a table starting at 1e-7° (or ending at 179.9999999°) was held
// constant out to 0° (180°) at a μ that rounds to the same double, and PiecewiseLinear1D threw
// std::invalid_argument, not a shvol::Error. Such an end angle now is the end.
TEST(TabulatedCsv, EndAnglesWhoseCosineRoundsToTheEnd) {
    const TabulatedPhase a =
        readPhaseTableCsv(writeCsv("near0.csv", "\x15 header\n1e-7,32\n19.999,0.5\n180,1e2\n"));
    EXPECT_EQ(a.table().nodes().size(), 3u);
    const TabulatedPhase b =
        readPhaseTableCsv(writeCsv("near180.csv", "0,1\n90,2\n179.9999999,3\n"));
    EXPECT_EQ(b.table().nodes().size(), 3u);
    EXPECT_DOUBLE_EQ(b.evalCos(-1) / b.evalCos(1), 3.0);
}

// Values are only relative. 1e308 everywhere made the integral overflow to inf (a
// std::invalid_argument escaped); 3e-308 in a 0.00001° forward peak made it so small that the
// normalisation 1/∫ was inf, and the phase function evaluated to inf and NaN.
TEST(TabulatedCsv, ExtremeValuesAreNormalised) {
    const TabulatedPhase big =
        readPhaseTableCsv(writeCsv("big.csv", "0,1e308\n90,1e308\n180,1e308\n"));
    EXPECT_NEAR(big.evalCos(0.3), 1 / (4 * Pi), 1e-12);
    const TabulatedPhase tiny =
        readPhaseTableCsv(writeCsv("tiny.csv", "0,3e-308\n0.00001,3e-308\n0.00002,0\n180,0\n"));
    EXPECT_TRUE(std::isfinite(tiny.evalCos(1.0)));
    EXPECT_GT(tiny.evalCos(1.0), 0);
    EXPECT_EQ(tiny.evalCos(0.0), 0);
    // Subnormal values (strtod flags them with ERANGE) are numbers too.
    const TabulatedPhase sub =
        readPhaseTableCsv(writeCsv("sub.csv", "0,1e-320\n90,5e-321\n180,1e-320\n"));
    EXPECT_NEAR(sub.evalCos(1.0) / sub.evalCos(-1.0), 1.0, 1e-12);
    EXPECT_GT(sub.evalCos(0.0), 0);
}

// Only regular files: /dev/zero (tabulated:file=/dev/zero) was read forever.
TEST(TabulatedCsv, OnlyRegularFiles) {
    EXPECT_EQ(messageOf([] { readPhaseTableCsv("/dev/zero"); }), "/dev/zero: not a regular file");
}

}  // namespace
}  // namespace shvol
