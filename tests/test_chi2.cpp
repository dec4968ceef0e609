// The chi2 harness's own arithmetic (tests/chi2.h): the incomplete gamma function behind
// every p-value, against closed forms, and the Sidak threshold. That the harness rejects
// wrong pdfs is shown with real samplers in tests/test_warp.cpp.
#include <cmath>

#include <gtest/gtest.h>

#include "chi2.h"

using namespace penumbra;

TEST(Chi2, IncompleteGammaMatchesClosedForms) {
    // Q(1, x) = e^-x; Q(1/2, x) = erfc(sqrt x); chi2 survival with 2 dof = e^(-x/2).
    for (double x : {0.0, 0.1, 1.0, 2.5, 10.0, 40.0}) {
        EXPECT_NEAR(test::regularizedGammaQ(1.0, x), std::exp(-x), 1e-12 + 1e-10 * std::exp(-x));
        EXPECT_NEAR(test::regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-12);
        EXPECT_NEAR(test::chi2Survival(x, 2), std::exp(-0.5 * x), 1e-12);
    }
    // Q(n, x) = e^-x sum_{k<n} x^k / k! for integer n, here with a large n as chi2 needs.
    for (double x : {150.0, 200.0, 260.0}) {
        double term = std::exp(-x), sum = 0.0;
        for (int k = 0; k < 200; ++k) {
            sum += term;
            term *= x / (k + 1);
        }
        EXPECT_NEAR(test::regularizedGammaQ(200.0, x), sum, 1e-10);
    }
    // The median of chi2 with many dof is close to dof (1 - 2/(9 dof))^3.
    const int dof = 4000;
    EXPECT_NEAR(test::chi2Survival(dof * std::pow(1.0 - 2.0 / (9.0 * dof), 3.0), dof), 0.5, 1e-3);
    EXPECT_NEAR(test::sidakThreshold(0.01, 1), 0.01, 1e-15);
    EXPECT_NEAR(test::sidakThreshold(0.01, 16), 1.0 - std::pow(0.99, 1.0 / 16.0), 1e-15);
}
