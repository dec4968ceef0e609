// Chi-square goodness-of-fit harness (see chi2.h). Both domains reduce to a grid of cells
// with row and column edges; the shared core integrates the pdf per cell by tensor
// Gauss-Legendre quadrature, pools, computes the statistic and p-value, and dumps tables.
#include "chi2.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "gpu_fixture.h"

namespace penumbra::test {

// ---- Incomplete gamma function (Numerical Recipes 3rd ed. 6.2, gser / gcf) ---------------

namespace {

// P(a, x) by its series, for x < a + 1.
double gammaPSeries(double a, double x) {
    double ap = a, del = 1.0 / a, sum = del;
    for (int n = 0; n < 100000; ++n) {
        ap += 1.0;
        del *= x / ap;
        sum += del;
        if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by its continued fraction (modified Lentz), for x >= a + 1.
double gammaQContinuedFraction(double a, double x) {
    const double tiny = std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon();
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double regularizedGammaQ(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0)) throw std::domain_error("regularizedGammaQ needs a > 0 and x >= 0");
    if (x == 0.0) return 1.0;
    if (x < a + 1.0) return 1.0 - gammaPSeries(a, x);
    return gammaQContinuedFraction(a, x);
}

double chi2Survival(double statistic, int dof) { return regularizedGammaQ(0.5 * dof, 0.5 * statistic); }

double sidakThreshold(double alpha, int numTests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / numTests); }

// ---- The shared core ----------------------------------------------------------------------

namespace {

constexpr double kMinExpected = 5.0;  // cells expected to hold fewer samples are pooled

// Gauss-Legendre nodes on [0, 1] and their weights (summing to 1), orders 4 and 5.
struct Rule {
    std::vector<double> x, w;
};
Rule gaussLegendre(int order) {
    Rule r;
    if (order == 4) {
        const double a = 0.3399810435848563, b = 0.8611363115940526;
        const double wa = 0.6521451548625461, wb = 0.3478548451374538;
        r.x = {-b, -a, a, b};
        r.w = {wb, wa, wa, wb};
    } else if (order == 5) {
        const double a = 0.5384693101056831, b = 0.9061798459386640;
        const double w0 = 0.5688888888888889, wa = 0.4786286704993665, wb = 0.2369268850561891;
        r.x = {-b, -a, 0.0, a, b};
        r.w = {wb, wa, w0, wa, wb};
    } else {
        throw std::logic_error("gaussLegendre: order 4 or 5");
    }
    for (double& x : r.x) x = 0.5 * (x + 1.0);
    for (double& w : r.w) w *= 0.5;
    return r;
}

// A rows x cols histogram with its cell edges; cell (i, j) spans rowEdges[i..i+1] x
// colEdges[j..j+1] in coordinates where the domain's measure is d(row) d(col).
struct Grid {
    std::string rowAxis, colAxis;
    std::vector<double> rowEdges, colEdges;
    size_t rows() const { return rowEdges.size() - 1; }
    size_t cols() const { return colEdges.size() - 1; }
};

struct Integrated {
    std::vector<double> expectedPerSample;  // integral of the pdf over each cell
    double integral = 0.0;
    double tolerance = 0.0;
};

// Integrates a pdf given in grid coordinates over every cell with the 5-point rule in each
// axis; the 4-point rule alongside bounds the error. For a pdf smooth inside each cell the
// 5-point rule's error is far below the difference of the two, so that difference (plus
// a floor for the float32 evaluation of the pdf, ~1e-6 relative) is a safe tolerance.
template <class Point, class MakePoint, class Pdf>
Integrated integrateCells(const Grid& grid, MakePoint makePoint, const Pdf& pdf) {
    const Rule hi = gaussLegendre(5), lo = gaussLegendre(4);
    const size_t cells = grid.rows() * grid.cols();
    std::vector<Point> points;
    points.reserve(cells * (hi.x.size() * hi.x.size() + lo.x.size() * lo.x.size()));
    for (size_t i = 0; i < grid.rows(); ++i)
        for (size_t j = 0; j < grid.cols(); ++j)
            for (const Rule* rule : {&hi, &lo})
                for (double a : rule->x)
                    for (double b : rule->x)
                        points.push_back(makePoint(grid.rowEdges[i] + a * (grid.rowEdges[i + 1] - grid.rowEdges[i]),
                                                   grid.colEdges[j] + b * (grid.colEdges[j + 1] - grid.colEdges[j])));
    const std::vector<double> values = pdf(points);
    if (values.size() != points.size()) throw std::logic_error("chi2: the pdf returned the wrong number of values");

    Integrated out;
    out.expectedPerSample.resize(cells);
    double integralLo = 0.0;
    size_t k = 0;
    for (size_t i = 0; i < grid.rows(); ++i)
        for (size_t j = 0; j < grid.cols(); ++j) {
            const double area = (grid.rowEdges[i + 1] - grid.rowEdges[i]) * (grid.colEdges[j + 1] - grid.colEdges[j]);
            double sums[2] = {0.0, 0.0};
            int r = 0;
            for (const Rule* rule : {&hi, &lo}) {
                for (double wa : rule->w)
                    for (double wb : rule->w) sums[r] += wa * wb * values[k++];
                ++r;
            }
            out.expectedPerSample[i * grid.cols() + j] = sums[0] * area;
            out.integral += sums[0] * area;
            integralLo += sums[1] * area;
        }
    out.tolerance = 4.0 * std::abs(out.integral - integralLo) + 1e-5 * std::abs(out.integral) + 1e-9;
    return out;
}

void dumpTables(const std::string& dumpName, const Grid& grid, const std::vector<double>& observed,
                const std::vector<double>& expected, size_t invalid, double invalidExpected, const Chi2Result& r) {
    if (dumpName.empty()) return;
    std::ofstream f(outputPath(dumpName + ".txt"));
    f << "# chi2 goodness-of-fit tables: " << r.message << "\n"
      << "# invalid samples: observed " << invalid << ", expected " << invalidExpected << "\n"
      << "# one line per cell, blank line between rows (gnuplot: splot '...' u 5:6:7 w pm3d;\n"
      << "# numpy: np.loadtxt, reshape to (" << grid.rows() << ", " << grid.cols() << "))\n"
      << "# row col " << grid.rowAxis << "_lo " << grid.rowAxis << "_hi " << grid.rowAxis << "_mid " << grid.colAxis
      << "_mid observed expected (observed-expected)/sqrt(expected)\n"
      << std::setprecision(9);
    for (size_t i = 0; i < grid.rows(); ++i) {
        for (size_t j = 0; j < grid.cols(); ++j) {
            const size_t c = i * grid.cols() + j;
            const double e = expected[c];
            f << i << ' ' << j << ' ' << grid.rowEdges[i] << ' ' << grid.rowEdges[i + 1] << ' '
              << 0.5 * (grid.rowEdges[i] + grid.rowEdges[i + 1]) << ' '
              << 0.5 * (grid.colEdges[j] + grid.colEdges[j + 1]) << ' ' << observed[c] << ' ' << e << ' '
              << (e > 0 ? (observed[c] - e) / std::sqrt(e) : 0.0) << '\n';
        }
        f << '\n';
    }
}

std::string fmt(double v) {
    std::ostringstream s;
    s << std::setprecision(6) << v;
    return s.str();
}

// Compares the histogram with N times the integrated pdf. `invalid` samples (declined by
// the sampler) form one more cell, expected to hold the mass the pdf misses.
Chi2Result compare(const Grid& grid, const std::vector<double>& observed, const Integrated& pdf, size_t numSamples,
                   size_t invalid, double significance, int numTests, const std::string& dumpName,
                   double declinedFraction = -1.0) {
    Chi2Result r;
    r.pdfIntegral = pdf.integral;
    r.integralTolerance = pdf.tolerance;
    r.threshold = sidakThreshold(significance, numTests);
    const double n = double(numSamples);

    std::vector<double> obs = observed, expected(pdf.expectedPerSample.size());
    for (size_t c = 0; c < expected.size(); ++c) expected[c] = n * pdf.expectedPerSample[c];
    // Missing mass beyond the quadrature error is what declined samples should account for.
    // A declined fraction known in closed form replaces it.
    const double missing = declinedFraction >= 0.0 ? declinedFraction : 1.0 - pdf.integral;
    const double invalidExpected =
        (declinedFraction >= 0.0 ? missing > 0.0 : missing > pdf.tolerance) ? n * missing : 0.0;
    obs.push_back(double(invalid));
    expected.push_back(invalidExpected);

    std::string failure;
    double outsideSupport = 0.0;
    for (size_t c = 0; c < expected.size(); ++c)
        if (expected[c] <= 0.0) outsideSupport += obs[c];
    if (pdf.integral > 1.0 + pdf.tolerance)
        failure = "pdf integrates to " + fmt(pdf.integral) + ", more than 1 (quadrature tolerance " +
                  fmt(pdf.tolerance) + ")";
    else if (invalid > 0 && invalidExpected == 0.0)
        failure = std::to_string(invalid) + " samples were declined (zero vector) but the pdf integrates to " +
                  fmt(pdf.integral) + ", i.e. 1";
    else if (outsideSupport > 0.0)
        failure = fmt(outsideSupport) + " samples fell in cells where the pdf integrates to 0 (outside its support)";

    // Pool cells expected to hold < kMinExpected samples, smallest first, as Mitsuba does;
    // a pool still too small absorbs the next cell(s).
    std::vector<size_t> order(expected.size());
    for (size_t c = 0; c < order.size(); ++c) order[c] = c;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double pooledObs = 0.0, pooledExp = 0.0, stat = 0.0;
    int pooledIn = 0, cellsUsed = 0;
    for (size_t c : order) {
        if (expected[c] <= 0.0) continue;  // cells outside the support: checked above
        if (expected[c] < kMinExpected || (pooledIn > 0 && pooledExp < kMinExpected)) {
            pooledObs += obs[c];
            pooledExp += expected[c];
            ++pooledIn;
        } else {
            stat += (obs[c] - expected[c]) * (obs[c] - expected[c]) / expected[c];
            ++cellsUsed;
        }
    }
    if (pooledIn > 0) {
        stat += (pooledObs - pooledExp) * (pooledObs - pooledExp) / pooledExp;
        ++cellsUsed;
    }
    r.statistic = stat;
    r.dof = cellsUsed - 1;
    if (failure.empty() && r.dof < 1) failure = "too few cells with expected count >= 5 (dof < 1)";
    if (r.dof >= 1) r.pValue = chi2Survival(stat, r.dof);

    const std::string figures = "chi2 = " + fmt(stat) + ", dof = " + std::to_string(r.dof) + ", p = " +
                                fmt(r.pValue) + ", threshold " + fmt(r.threshold) + "; pdf integral " +
                                fmt(pdf.integral) + " +- " + fmt(pdf.tolerance) + "; " +
                                std::to_string(pooledIn) + " cells pooled";
    if (failure.empty() && !(r.pValue >= r.threshold))
        failure = "histogram does not match the pdf: p = " + fmt(r.pValue) + " < threshold " + fmt(r.threshold);
    r.passed = failure.empty();
    r.message = r.passed ? figures : failure + " (" + figures + ")";
    if (!r.passed) dumpTables(dumpName, grid, observed, expected, invalid, invalidExpected, r);
    return r;
}

}  // namespace

// ---- Sphere -----------------------------------------------------------------------------

Chi2Result chi2TestSphere(const std::vector<glm::vec3>& directions, const DirectionPdf& pdf,
                          const SphereChi2Options& o) {
    const double cap = o.capOneMinusCos;
    if (!(cap > 0.0 && cap <= 2.0) || o.thetaRes < 1 || o.phiRes < 1)
        throw std::invalid_argument("chi2TestSphere: need 0 < cap <= 2 and positive resolutions");
    const double twoPi = 2.0 * std::numbers::pi;

    // Rows in u = 1 - cos(theta), columns in phi: d(omega) = du dphi, so equal du dphi means
    // equal solid angle.
    Grid grid{"one_minus_cos_theta", "phi", {}, {}};
    for (int i = 0; i <= o.thetaRes; ++i) grid.rowEdges.push_back(cap * i / o.thetaRes);
    // Outside the cap the rows widen geometrically (edges cap * ratio^i, ratio = (2/cap)^(1/res)):
    // a lobe's tail just past the cap then falls on rows narrow enough to integrate.
    if (cap < 2.0) {
        const double ratio = std::pow(2.0 / cap, 1.0 / o.thetaRes);
        for (int i = 1; i < o.thetaRes; ++i) grid.rowEdges.push_back(cap * std::pow(ratio, i));
        grid.rowEdges.push_back(2.0);
    }
    for (int j = 0; j <= o.phiRes; ++j) grid.colEdges.push_back(twoPi * j / o.phiRes);

    // Histogram. 1 - cos(theta) from x and y near the pole (no cancellation); samples within
    // float rounding (1e-6 relative) of the cap's edge belong to the cap.
    std::vector<double> observed(grid.rows() * grid.cols(), 0.0);
    size_t invalid = 0, nonFinite = 0, nonUnit = 0;
    for (const glm::vec3& v : directions) {
        const double x = v.x, y = v.y, z = v.z;
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
            ++nonFinite;
            continue;
        }
        const double len2 = x * x + y * y + z * z;
        if (len2 == 0.0) {
            ++invalid;
            continue;
        }
        if (std::abs(len2 - 1.0) > 1e-4) {
            ++nonUnit;
            continue;
        }
        const double u = std::clamp(z > 0.0 ? (x * x + y * y) / (1.0 + z) : 1.0 - z, 0.0, 2.0);
        int row;
        if (u <= cap * (1.0 + 1e-6)) {
            row = std::min(int(u / cap * o.thetaRes), o.thetaRes - 1);
        } else {
            // The outer row whose edges enclose u.
            row = int(std::upper_bound(grid.rowEdges.begin() + o.thetaRes + 1, grid.rowEdges.end(), u) -
                      grid.rowEdges.begin()) - 1;
            row = std::clamp(row, o.thetaRes, int(grid.rows()) - 1);
        }
        double phi = std::atan2(y, x);
        if (phi < 0.0) phi += twoPi;
        const int col = std::min(int(phi / twoPi * o.phiRes), o.phiRes - 1);
        observed[size_t(row) * grid.cols() + size_t(col)] += 1.0;
    }

    Integrated integrated = integrateCells<glm::vec3>(
        grid,
        [](double u, double phi) {
            const double sinTheta = std::sqrt(std::max(0.0, u * (2.0 - u)));
            return glm::vec3(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(1.0 - u));
        },
        pdf);
    integrated.tolerance += o.evaluationTolerance;
    Chi2Result r = compare(grid, observed, integrated, directions.size(), invalid, o.significance, o.numTests,
                           o.dumpName, o.declinedFraction);
    if (nonFinite + nonUnit > 0) {
        r.passed = false;
        r.message = std::to_string(nonFinite) + " samples are NaN/inf and " + std::to_string(nonUnit) +
                    " are not unit vectors (" + r.message + ")";
    }
    return r;
}

// ---- Unit square ------------------------------------------------------------------------

Chi2Result chi2TestSquare(const std::vector<glm::dvec2>& points, const SquarePdf& pdf, const SquareChi2Options& o) {
    if (o.res < 1) throw std::invalid_argument("chi2TestSquare: resolution must be positive");
    Grid grid{"s", "t", {}, {}};
    for (int i = 0; i <= o.res; ++i) grid.rowEdges.push_back(double(i) / o.res);
    grid.colEdges = grid.rowEdges;

    std::vector<double> observed(grid.rows() * grid.cols(), 0.0);
    size_t invalid = 0, outside = 0;
    const double slack = 1e-6;  // float rounding of the mapped samples
    for (const glm::dvec2& p : points) {
        if (std::isnan(p.x) || std::isnan(p.y)) {
            ++invalid;
            continue;
        }
        if (!(p.x >= -slack && p.x <= 1.0 + slack && p.y >= -slack && p.y <= 1.0 + slack)) {
            ++outside;
            continue;
        }
        const int i = std::clamp(int(p.x * o.res), 0, o.res - 1);
        const int j = std::clamp(int(p.y * o.res), 0, o.res - 1);
        observed[size_t(i) * grid.cols() + size_t(j)] += 1.0;
    }
    Integrated integrated =
        integrateCells<glm::dvec2>(grid, [](double s, double t) { return glm::dvec2(s, t); }, pdf);
    integrated.tolerance += o.evaluationTolerance;
    Chi2Result r =
        compare(grid, observed, integrated, points.size(), invalid, o.significance, o.numTests, o.dumpName,
                o.declinedFraction);
    if (outside > 0) {
        r.passed = false;
        r.message = std::to_string(outside) + " samples lie outside [0,1]^2 (" + r.message + ")";
    }
    return r;
}

// ---- Discrete outcomes --------------------------------------------------------------------

Chi2Result chi2TestDiscrete(const std::vector<double>& counts, const std::vector<double>& probabilities,
                            size_t declined, const DiscreteChi2Options& o) {
    if (counts.size() != probabilities.size() || counts.empty())
        throw std::invalid_argument("chi2TestDiscrete: one probability per outcome, at least one outcome");
    // One row of cells, one per outcome; the probabilities are exact, so the only
    // "quadrature" error is the rounding of their sum.
    Grid grid{"row", "outcome", {0.0, 1.0}, {}};
    for (size_t k = 0; k <= counts.size(); ++k) grid.colEdges.push_back(double(k));
    Integrated exact;
    exact.expectedPerSample = probabilities;
    for (double p : probabilities) exact.integral += p;
    exact.tolerance = 1e-12 * double(probabilities.size());
    double total = double(declined);
    for (double c : counts) total += c;
    return compare(grid, counts, exact, size_t(total), declined, o.significance, o.numTests, o.dumpName);
}

}  // namespace penumbra::test
