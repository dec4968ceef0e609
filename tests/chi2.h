// Chi-square goodness-of-fit tests of a sampler against its own pdf, for warps now and
// for light and BSDF sampling later. Samples are histogrammed; the expected count of each
// cell is N times the pdf integrated over the cell by quadrature, with the pdf evaluated
// by the caller (normally a GLSL kernel, so the shader's pdf is what is tested). Follows
// Mitsuba 3's chi2 harness (python/mitsuba/chi2.py) and Nori's src/chi2test.cpp: cells
// with expected count < 5 are pooled, the significance level is Sidak-corrected for the
// number of tests, and a failure says why and dumps its tables under build/test-output/.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::test {

struct Chi2Result {
    bool passed = false;            // chi2 accepted and no hard failure (see message)
    double pValue = 0.0;            // P(chi2_dof >= statistic)
    double statistic = 0.0;         // sum over pooled cells of (observed - expected)^2 / expected
    int dof = 0;                    // pooled cells - 1
    double threshold = 0.0;         // p-values below this fail: 1 - (1 - alpha)^(1 / numTests)
    double pdfIntegral = 0.0;       // integral of the pdf over the whole domain (quadrature)
    double integralTolerance = 0.0; // bound on the quadrature error of pdfIntegral
    std::string message;            // one line: why it failed, or the figures when it passed
};

// ---- Directions on the unit sphere ------------------------------------------------------

// The pdf (density w.r.t. solid angle) at many unit directions at once.
using DirectionPdf = std::function<std::vector<double>(const std::vector<glm::vec3>&)>;

struct SphereChi2Options {
    // Cells are equal-area: rows uniform in 1 - cos(theta) (the solid angle of a zone is
    // 2 pi times its height), columns uniform in phi.
    int thetaRes = 32;
    int phiRes = 64;
    // Zoom on the cap {1 - cos(theta) <= cap} about +z: thetaRes rows cover the cap and,
    // when cap < 2, another thetaRes rows, widening geometrically, cover the rest. Narrow lobes and
    // small cones need this; the whole sphere is cap = 2. A support boundary (hemisphere,
    // cone) should fall on a row edge: the quadrature is accurate only for pdfs that are
    // smooth inside each cell.
    double capOneMinusCos = 2.0;
    double significance = 0.01;  // alpha of one test, before the Sidak correction
    int numTests = 1;            // tests of this kind in the file (Sidak correction)
    std::string dumpName;        // on failure: build/test-output/<dumpName>.txt
    // Bound on the error of the pdf's integral that comes from evaluating the pdf itself
    // (float geometry that is ill-conditioned somewhere, e.g. rays grazing a sphere), added
    // to the quadrature tolerance; the caller derives it. 0 for pdfs good to float precision.
    double evaluationTolerance = 0.0;
    // When >= 0: the probability that the sampler declines, known in closed form; the
    // declined samples are compared with it instead of with 1 - integral (which carries the
    // evaluation tolerance). The caller checks the integral against it.
    double declinedFraction = -1.0;
};

// `directions`: the sampler's output, unit vectors in the pdf's frame. A zero vector marks
// a sample the sampler declined ("no sample"); such samples are compared with the mass
// the pdf misses, 1 - integral, as a cell of their own. NaN/inf or non-unit vectors fail.
Chi2Result chi2TestSphere(const std::vector<glm::vec3>& directions, const DirectionPdf& pdf,
                          const SphereChi2Options& options);

// ---- Points in the unit square ----------------------------------------------------------

// The density w.r.t. ds dt at many points (s, t) of [0,1]^2 at once. Planar samplers
// (disk, triangle) are tested by mapping their domain to the square; the density passed
// here then includes the Jacobian of that map.
using SquarePdf = std::function<std::vector<double>(const std::vector<glm::dvec2>&)>;

struct SquareChi2Options {
    int res = 64;  // res x res equal cells
    double significance = 0.01;
    int numTests = 1;
    std::string dumpName;
    double evaluationTolerance = 0.0;  // as in SphereChi2Options
    double declinedFraction = -1.0;    // as in SphereChi2Options
};

// `points`: samples mapped to [0,1]^2; NaN marks a declined sample (as above).
Chi2Result chi2TestSquare(const std::vector<glm::dvec2>& points, const SquarePdf& pdf,
                          const SquareChi2Options& options);

// ---- Discrete outcomes ------------------------------------------------------------------

struct DiscreteChi2Options {
    double significance = 0.01;
    int numTests = 1;
    std::string dumpName;
};

// `counts[k]`: how often outcome k was drawn; `probabilities[k]`: its exact probability.
// Probabilities may sum to less than 1: the rest is the chance that the sampler declines,
// compared with `declined` as one more outcome (as for the continuous tests above).
Chi2Result chi2TestDiscrete(const std::vector<double>& counts, const std::vector<double>& probabilities,
                            size_t declined, const DiscreteChi2Options& options);

// ---- Building blocks --------------------------------------------------------------------

// Regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a), by series
// for x < a + 1 and by continued fraction otherwise (Numerical Recipes 3rd ed. 6.2).
double regularizedGammaQ(double a, double x);
// P(X >= statistic) for X chi-square distributed with dof degrees of freedom.
double chi2Survival(double statistic, int dof);
// Per-test significance so that numTests independent tests at alpha fail together with
// probability alpha (Sidak): 1 - (1 - alpha)^(1 / numTests).
double sidakThreshold(double alpha, int numTests);

}  // namespace penumbra::test
