// tumble-dump on input it cannot use: one line on stderr naming the problem,
// exit 1 for a bad recording and 2 for bad usage.
#include <gtest/gtest.h>

#include "test/fixtures.hpp"
#include "test/tools/dump/dump_runner.hpp"

namespace tumble::test {
namespace {

TEST(DumpBadInput, MissingFileExitsOneNamingTheFile) {
  const std::string missing = (std::filesystem::temp_directory_path() / "tumble-dump-no-such-file.pcap").string();
  for (const char* kind : {"rs16", "mti"}) {
    const DumpRun run = run_dump({kind, missing});
    EXPECT_EQ(run.exit_code, 1) << kind;
    EXPECT_TRUE(run.out.empty()) << kind;
    EXPECT_NE(run.err.find(missing), std::string::npos) << kind << ": " << run.err;
    EXPECT_EQ(lines_of(run.err).size(), 1u) << kind << ": " << run.err;
  }
}

TEST(DumpBadInput, WrongLinkTypeExitsOne) {
  TUMBLE_REQUIRE_FIXTURE("rs16/rs16_synthetic.pcap");
  const DumpRun run = run_dump({"mti", fixture_path("rs16/rs16_synthetic.pcap").string()});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("link type"), std::string::npos) << run.err;
  EXPECT_EQ(lines_of(run.err).size(), 1u) << run.err;
}

TEST(DumpBadInput, UsageErrorsExitTwo) {
  EXPECT_EQ(run_dump({}).exit_code, 2);
  EXPECT_EQ(run_dump({"rs16"}).exit_code, 2);
  EXPECT_EQ(run_dump({"rs16", "--clock", "sundial", "x.pcap"}).exit_code, 2);
  const DumpRun split = run_dump({"rs16", "--split-azimuth-deg", "400", "x.pcap"});
  EXPECT_EQ(split.exit_code, 2);
  EXPECT_NE(split.err.find("split_azimuth_deg"), std::string::npos) << split.err;
  EXPECT_EQ(run_dump({"rs16", "--msop-port", "7788", "x.pcap"}).exit_code, 2);
  EXPECT_EQ(run_dump({"mti", "--rate-hz", "0", "x.bin"}).exit_code, 2);
}

}  // namespace
}  // namespace tumble::test
