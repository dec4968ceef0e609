// SlowStepNotice: the "compiling kernels..." line appears only for a step that outlasts its
// delay, and is erased when the step ends.
#include <chrono>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "cli/slow_step_notice.h"

using namespace penumbra;
using namespace std::chrono_literals;

TEST(SlowStepNotice, AFastStepPrintsNothing) {
    testing::internal::CaptureStderr();
    {
        SlowStepNotice notice("compiling kernels...", true, 10s);
        EXPECT_FALSE(notice.shown());
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(SlowStepNotice, ASlowStepShowsTheLineThenErasesIt) {
    testing::internal::CaptureStderr();
    {
        SlowStepNotice notice("compiling kernels...", true, 20ms);
        for (int i = 0; i < 500 && !notice.shown(); ++i) std::this_thread::sleep_for(10ms);
        EXPECT_TRUE(notice.shown());
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("penumbra: compiling kernels..."), std::string::npos) << err;
    // Ends with the line blanked and the cursor back at its start, so the next line is clean.
    ASSERT_GE(err.size(), 2u);
    EXPECT_EQ(err.back(), '\r') << err;
    EXPECT_EQ(err.find('\n'), std::string::npos) << err;
}

TEST(SlowStepNotice, DisabledPrintsNothingHoweverLong) {
    testing::internal::CaptureStderr();
    {
        SlowStepNotice notice("compiling kernels...", false, 1ms);
        std::this_thread::sleep_for(30ms);
        EXPECT_FALSE(notice.shown());
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}
