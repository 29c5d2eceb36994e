// The C ABI's information functions, status names and the per-thread last error.
#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "c_api_common.hpp"
#include "setbound/core/validate.hpp"
// The umbrella header must compile on its own terms for C++ users (the installed-consumer test
// includes only the headers it uses, to keep its build short).
#include "setbound/setbound.hpp"

TEST(CApiCore, VersionAndAbi) {
  EXPECT_STREQ(sb_version(), SETBOUND_TEST_VERSION);
  EXPECT_EQ(sb_abi_version(), SETBOUND_TEST_ABI_VERSION);
}

TEST(CApiCore, StatusNamesCoverEveryCode) {
  EXPECT_STREQ(sb_status_name(SB_OK), "ok");
  EXPECT_STREQ(sb_status_name(SB_ERR_DIMENSION), "dimension mismatch");
  EXPECT_STREQ(sb_status_name(SB_ERR_NOT_POSITIVE_DEFINITE), "not positive definite");
  for (int code = SB_ERR_INCONSISTENT; code <= SB_ERR_INVALID_ARGUMENT; ++code)
    EXPECT_STRNE(sb_status_name(code), "unknown status") << code;
  EXPECT_STREQ(sb_status_name(-1000), "unknown status");
  EXPECT_STREQ(sb_status_name(3), "unknown status");
}

TEST(CApiCore, GuardTranslatesExceptionsAndKeepsMessagePerThread) {
  using namespace setbound;
  int rc = capi::guard("sb_test", [] { throw NotSymmetricError("P: matrix is not symmetric"); });
  EXPECT_EQ(rc, SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(std::string(sb_last_error()), "sb_test: P: matrix is not symmetric");

  // Another thread has its own (empty) message and its failure does not leak here.
  std::string other_before, other_after;
  std::thread t([&] {
    other_before = sb_last_error();
    capi::guard("sb_other", [] { throw DimensionError("x: wrong"); });
    other_after = sb_last_error();
  });
  t.join();
  EXPECT_EQ(other_before, "");
  EXPECT_EQ(other_after, "sb_other: x: wrong");
  EXPECT_EQ(std::string(sb_last_error()), "sb_test: P: matrix is not symmetric");

  EXPECT_EQ(capi::guard("sb_ok", [] {}), SB_OK);
  EXPECT_EQ(capi::guard("sb_std", [] { throw std::runtime_error("boom"); }), SB_ERR_INTERNAL);
  EXPECT_NE(std::string(sb_last_error()).find("boom"), std::string::npos);
}

TEST(Validate, ChecksNameTheArgument) {
  using namespace setbound;
  Eigen::MatrixXd P(2, 2);
  P << 1, 2, 0, 1;
  try {
    require_symmetric(P, "P");
    FAIL() << "expected NotSymmetricError";
  } catch (const NotSymmetricError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("P:", 0), 0u);
  }
  P << 1, 2, 2, 1;  // symmetric, eigenvalues 3 and -1
  EXPECT_THROW(require_positive_definite(P, "P"), NotPositiveDefiniteError);
  P(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(require_finite(P, "P"), NotFiniteError);
  EXPECT_THROW(require_shape(Eigen::MatrixXd(2, 3), 3, 2, "M"), DimensionError);
  EXPECT_THROW(require_positive(0.0, "rho"), InvalidArgumentError);
  P << 2, 1, 1, 2;
  EXPECT_NO_THROW(require_positive_definite(P, "P"));
}
