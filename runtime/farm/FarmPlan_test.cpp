// How moire farm cuts a request into shards, and the scripts it hands to Slurm: the cuts are
// checked against a brute-force count of frames and pixels, the shell text by running it in
// bash (with a stand-in sbatch that records what it is given).
#include "runtime/farm/FarmPlan.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace moire::farm;
namespace fs = std::filesystem;

namespace {

// Runs `command` in sh; its standard output, and its exit status in `status`.
std::string run(const std::string& command, int* status = nullptr) {
    FILE* p = ::popen(command.c_str(), "r");
    REQUIRE(p);
    std::string out;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    int rc = ::pclose(p);
    if (status) *status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    return out;
}

void writeFile(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

} // namespace

TEST_CASE("splitFrames: contiguous ranges that cover the clip, as even as they can be") {
    for (int64_t first : {0, 5, 1000})
        for (int64_t count : {1, 2, 7, 48, 100})
            for (int shards : {1, 2, 5, 6, 48, 60}) {
                CAPTURE(first);
                CAPTURE(count);
                CAPTURE(shards);
                std::vector<FrameShard> s = splitFrames(first, first + count - 1, shards);
                CHECK(static_cast<int64_t>(s.size()) == std::min<int64_t>(shards, count));
                int64_t next = first, shortest = count, longest = 0;
                for (const FrameShard& r : s) {
                    CHECK(r.first == next);
                    CHECK(r.last >= r.first);
                    shortest = std::min(shortest, r.last - r.first + 1);
                    longest = std::max(longest, r.last - r.first + 1);
                    next = r.last + 1;
                }
                CHECK(next == first + count);
                CHECK(longest - shortest <= 1);
            }
    std::vector<FrameShard> s = splitFrames(0, 47, 6);
    REQUIRE(s.size() == 6);
    CHECK((s[1].first == 8 && s[1].last == 15));
}

TEST_CASE("splitRegions: tiles that cover every pixel once, nearest to square") {
    for (auto [w, h] : {std::pair{64, 48}, {1, 1}, {3, 100}, {601, 399}, {5, 2}})
        for (int shards : {1, 2, 4, 6, 7, 12}) {
            CAPTURE(w);
            CAPTURE(h);
            CAPTURE(shards);
            std::vector<int> covered(static_cast<size_t>(w) * h, 0);
            for (const Region& r : splitRegions(w, h, shards)) {
                REQUIRE((0 <= r.x0 && r.x0 < r.x1 && r.x1 <= w));
                REQUIRE((0 <= r.y0 && r.y0 < r.y1 && r.y1 <= h));
                for (int y = r.y0; y < r.y1; ++y)
                    for (int x = r.x0; x < r.x1; ++x) ++covered[static_cast<size_t>(y) * w + x];
            }
            CHECK(std::count(covered.begin(), covered.end(), 1) ==
                  static_cast<long>(covered.size()));
        }
    // A square frame in four: 2 x 2; a 3:2 frame in six: 3 x 2 square tiles; a prime: strips
    // across the longer side.
    std::vector<Region> q = splitRegions(100, 100, 4);
    REQUIRE(q.size() == 4);
    CHECK((q[0].x1 == 50 && q[0].y1 == 50 && q[3].x0 == 50 && q[3].y0 == 50));
    std::vector<Region> six = splitRegions(600, 400, 6);
    REQUIRE(six.size() == 6);
    for (const Region& r : six) CHECK((r.x1 - r.x0 == 200 && r.y1 - r.y0 == 200));
    std::vector<Region> strips = splitRegions(700, 100, 7);
    REQUIRE(strips.size() == 7);
    CHECK((strips[6].x0 == 600 && strips[6].y0 == 0 && strips[6].y1 == 100));
    // More tiles than a side has pixels: fewer tiles, never an empty one.
    CHECK(splitRegions(1, 1, 4).size() == 1);
}

TEST_CASE("shellQuote: the shell reads back every word as it was") {
    const std::vector<std::string> words = {"plain", "a b",        "it's",        "$HOME",
                                            "`id`",  "",           "back\\slash", "\"q\"",
                                            "*",     "f_%04d.png", "x\ny",        "--size=64x48"};
    std::string out = run("printf '%s\\0' " + shellCommand(words));
    std::vector<std::string> back;
    for (size_t at = 0, end; (end = out.find('\0', at)) != std::string::npos; at = end + 1)
        back.push_back(out.substr(at, end - at));
    CHECK(back == words);
    CHECK(shellQuote("frames/f_%04d.png") == "frames/f_%04d.png"); // left readable
}

TEST_CASE("makeScripts: a shard per array task, the join, and the submission's sbatch calls") {
    moire::test::TempDir dir("farm");
    const fs::path work = fs::path(dir.path()) / "work dir";
    fs::create_directories(work);
    FarmJob job;
    job.name = "moire-test";
    job.workdir = work.string();
    job.partition = "gpu";
    job.sbatchArgs = {"--time=10", "--account=it's"};
    job.shards = {{"printf", "%s|", "task 0", "it's $HOME"}, {"printf", "%s|", "task 1"}};
    job.join = {{"printf", "%s|", "join"}, {"printf", "%s|", "done"}};
    FarmScripts s = makeScripts(job);
    writeFile(work / "shard.sh", s.shard);
    writeFile(work / "join.sh", s.join);
    writeFile(work / "submit.sh", s.submit);

    const std::string shard = "bash '" + (work / "shard.sh").string() + "'";
    CHECK(run("SLURM_ARRAY_TASK_ID=0 " + shard) == "task 0|it's $HOME|");
    CHECK(run("SLURM_ARRAY_TASK_ID=1 " + shard) == "task 1|");
    int status = 0;
    run("SLURM_ARRAY_TASK_ID=2 " + shard + " 2>/dev/null", &status);
    CHECK(status == 2);
    run(shard + " 2>/dev/null", &status); // not run by Slurm
    CHECK(status != 0);
    CHECK(run("bash '" + (work / "join.sh").string() + "'") == "join|done|");
    CHECK(fs::exists(work / "joined")); // what submit.sh --wait looks for

    // A stand-in sbatch: records each call's arguments, one a line, and answers a job id.
    const fs::path bin = fs::path(dir.path()) / "bin";
    fs::create_directories(bin);
    writeFile(bin / "sbatch", "#!/bin/bash\n"
                              "n=$(( $(ls \"$LOG\" 2>/dev/null | wc -l) + 1 ))\n"
                              "mkdir -p \"$LOG\"; printf '%s\\n' \"$@\" > \"$LOG/$n\"\n"
                              "echo \"$(( 40 + n ));cluster\"\n");
    fs::permissions(bin / "sbatch", fs::perms::owner_all);
    const fs::path log = fs::path(dir.path()) / "calls";
    std::string out = run("PATH='" + bin.string() + "':$PATH LOG='" + log.string() + "' bash '" +
                              (work / "submit.sh").string() + "'",
                          &status);
    CHECK(status == 0);
    CHECK(out.find("job array 41") != std::string::npos);
    CHECK(out.find("join: job 42") != std::string::npos);
    const std::string w = work.string();
    CHECK(moire::test::readFile(log / "1") ==
          "--parsable\n--job-name=moire-test-shard\n--array=0-1\n--output=" + w +
              "/logs/shard-%a.log\n--partition=gpu\n--time=10\n"
              "--account=it's\n" +
              w + "/shard.sh\n");
    CHECK(moire::test::readFile(log / "2") ==
          "--parsable\n--job-name=moire-test-join\n"
          "--dependency=afterok:41\n--kill-on-invalid-dep=yes\n--output=" +
              w +
              "/logs/join.log\n--partition=gpu\n--time=10\n"
              "--account=it's\n" +
              w + "/join.sh\n");
    job.wait = true;
    CHECK(makeScripts(job).submit.find("--output='" + w +
                                       "'/logs/join.log --partition=gpu "
                                       "--time=10 '--account=it'\\''s' --wait") !=
          std::string::npos);
}
