// main() of every property-test executable: one knob scales all case counts, the seed is always
// printed, and RC_PARAMS given by the user wins.
//   DCAD_PROP_SCALE=k   run k × the default number of cases of every property (default 1)
//   RC_PARAMS="seed=… max_success=…"   (space-separated) reproduce a run exactly
#include "tally.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  const char* user = std::getenv("RC_PARAMS");
  std::string params = user ? user : "";
  const char* scale_env = std::getenv("DCAD_PROP_SCALE");
  const double scale = scale_env ? std::atof(scale_env) : 1.0;
  if (params.find("max_success") == std::string::npos)
    params += " max_success=" + std::to_string(static_cast<long>(dcad::test::kDefaultCases * (scale > 0 ? scale : 1)));
  if (params.find("seed") == std::string::npos)
    params += " seed=" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() % 1000000007);
  if (params.find("max_size") == std::string::npos) params += " max_size=100";
  setenv("RC_PARAMS", params.c_str(), 1);
  bool listing = false;  // ctest's test discovery reads the list from stdout: nothing else there
  for (int i = 1; i < argc; ++i) listing = listing || std::string(argv[i]) == "--gtest_list_tests";
  if (!listing) std::cout << "dcad proptests: reproduce with RC_PARAMS=\"" << params << "\"" << std::endl;
  testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  if (!listing) dcad::test::print_tally(std::cout);
  return rc;
}
