#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct CommandResult {
  int status = -1;
  std::string output;  // stdout + stderr
};

CommandResult Wearscar(const std::string& args) {
  CommandResult r;
  const std::string cmd = std::string(WEARSCAR_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
    r.output.append(buf.data(), n);
  const int st = pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

const std::string kData = std::string(WEARSCAR_TEST_DATA) + "/force/";

TEST(Cli, VersionAndHelp) {
  CommandResult v = Wearscar("version");
  EXPECT_EQ(v.status, 0);
  EXPECT_EQ(v.output.rfind("wearscar 0.", 0), 0u) << v.output;
  CommandResult h = Wearscar("--help");
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.output.find("simulate"), std::string::npos);
  EXPECT_NE(h.output.find("force"), std::string::npos);
}

TEST(Cli, NoSubcommandOrUnknownOptionExitsTwo) {
  EXPECT_EQ(Wearscar("").status, 2);
  EXPECT_EQ(Wearscar("force --no-such-option x").status, 2);
}

TEST(Cli, BadForceFileIsOneLineAndStatusTwo) {
  const CommandResult r = Wearscar("force " + kData + "bad_ragged.csv -o " +
                                   ::testing::TempDir() + "/cli-bad");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("bad_ragged.csv: line 31: ragged row"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(
      std::filesystem::exists(::testing::TempDir() + "/cli-bad/cycles.csv"));
}

TEST(Cli, SimulateThenAnalyseRecoversMu) {
  const std::string dir = ::testing::TempDir() + "/cli-sim";
  const CommandResult s = Wearscar(
      "simulate --case B-TL-L --cycles 40 --scan-cols 64 --scan-rows 48 -o " +
      dir);
  ASSERT_EQ(s.status, 0) << s.output;
  const CommandResult f = Wearscar(
      "force " + dir + "/B-TL-L.force.csv --running-in 20 -o " + dir + "/out");
  ASSERT_EQ(f.status, 0) << f.output;
  std::ifstream csv(dir + "/out/cycles.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(
      header.rfind(
          "cycle,mu_hat_force,J_force,mu_hat_scan,J_scan,samples,mu_mean", 0),
      0u)
      << header;
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 40);
  EXPECT_NE(f.output.find("mu-hat, k from P     0.1"), std::string::npos)
      << f.output;
  EXPECT_NE(f.output.find("verdict: explained by wear-scar interaction"),
            std::string::npos)
      << f.output;
}

TEST(Cli, FuseWritesResultsAndFlagsTheElasticCase) {
  const std::string dir = ::testing::TempDir() + "/cli-fuse";
  const CommandResult s =
      Wearscar("simulate --case S-RL-R --cycles 120 -o " + dir);
  ASSERT_EQ(s.status, 0) << s.output;
  const CommandResult f =
      Wearscar("fuse --force " + dir + "/S-RL-R.force.csv --scan " + dir +
               "/S-RL-R.scan.gsf --running-in 60 --compare-cycles 40 -o " +
               dir + "/out");
  ASSERT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("verdict: not explained by wear-scar interaction"),
            std::string::npos)
      << f.output;
  for (const char* file : {"result.json",
                           "cycles.csv",
                           "loops.csv",
                           "detail.csv",
                           "cost_curve.csv",
                           "profiles.csv",
                           "centreline.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + file)) << file;
  }
  // No temporary file left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir + "/out")) {
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
  }
}

TEST(Cli, FuseWithUnreadableScanExitsTwoNamingIt) {
  const std::string dir = ::testing::TempDir() + "/cli-fuse-bad";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/bad.vk4") << "VK4_ but far too short";
  const CommandResult f =
      Wearscar("fuse --force " + kData + "generic.csv --scan " + dir +
               "/bad.vk4 -o " + dir + "/out");
  EXPECT_EQ(f.status, 2);
  EXPECT_NE(f.output.find(dir + "/bad.vk4: byte 0: truncated"),
            std::string::npos)
      << f.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

}  // namespace
