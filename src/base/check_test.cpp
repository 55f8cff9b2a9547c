#include "base/check.h"

#include <gtest/gtest.h>

namespace raycast {
namespace {

TEST(CheckTest, ADcheckEvaluatesItsConditionExactlyWhenDchecksAreOn) {
    int evaluations = 0;
    RAYCAST_DCHECK(++evaluations == 1);
    EXPECT_EQ(evaluations, RAYCAST_DCHECKS_ENABLED ? 1 : 0);
}

TEST(CheckTest, AFailedDcheckAbortsWithTheConditionWhenDchecksAreOn) {
    if (!RAYCAST_DCHECKS_ENABLED) {
        RAYCAST_DCHECK(1 + 1 == 3);  // compiled, never evaluated: nothing happens
        GTEST_SKIP() << "this build does not check RAYCAST_DCHECK (Release)";
    }
    EXPECT_DEATH(RAYCAST_DCHECK(1 + 1 == 3), "internal error: check failed: 1 \\+ 1 == 3");
}

// docs/reliability.md: the sanitizer build (RelWithDebInfo, so NDEBUG) checks the invariants too.
TEST(CheckTest, SanitizerBuildsCheckDchecks) {
#if defined(__SANITIZE_ADDRESS__)
    EXPECT_EQ(RAYCAST_DCHECKS_ENABLED, 1);
#else
    GTEST_SKIP() << "not a sanitizer build";
#endif
}

}  // namespace
}  // namespace raycast
