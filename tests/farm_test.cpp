// moire farm without a cluster: the video join (farm encode) gives the bytes `moire clip`
// writes, --plan prints the scripts and touches nothing, and a request that cannot work is
// refused before anything is submitted. tests/farm runs it on a real Slurm.
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <fmt/format.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

// An animated scene with a param, in a fresh directory that the commands run in.
const char* kScene = "scene { size = (48, 32) }\n"
                     "timing drift { period = 0.5; mode = loop }\n"
                     "layer { family = circles; spacing = ramp(drift, 3, 5) }\n"
                     "param gap = 4 in 2 .. 8\n"
                     "layer { family = circles; spacing = gap; offset = (0.4, 0) }\n";

test::CommandResult moireIn(const test::TempDir& dir, const std::string& args,
                            const std::string& env = "") {
    return test::runCommand("cd '" + dir.path() + "' && " + env + " '" + test::moireBinary() +
                            "' " + args);
}

} // namespace

TEST_CASE("farm encode of a clip's frames rendered in pieces is byte for byte the clip") {
    if (test::runCommand("command -v ffmpeg >/dev/null").status != 0) {
        test::skip("ffmpeg is not installed");
        return;
    }
    test::TempDir dir("farm");
    dir.write("anim.moire", kScene);
    // The pieces as a farm's shards render them: uneven ranges, 8-bit PNG frames.
    for (const char* range : {"0..4", "5..5", "6..11"}) {
        auto r = moireIn(dir, fmt::format("clip anim.moire --fps 12 --frames {} --depth 8 "
                                          "-o frames/f_%03d.png -q --backend interp",
                                          range));
        INFO(r.err);
        REQUIRE(r.status == 0);
    }
    for (const char* ext : {"mp4", "webm", "gif"}) {
        CAPTURE(ext);
        auto joined = moireIn(
            dir,
            fmt::format("farm encode frames/f_%03d.png --frames 0..11 --fps 12 -o joined.{}", ext));
        INFO(joined.err);
        REQUIRE(joined.status == 0);
        auto whole = moireIn(
            dir, fmt::format("clip anim.moire --fps 12 --frames 12 -o whole.{} -q --backend interp",
                             ext));
        INFO(whole.err);
        REQUIRE(whole.status == 0);
        const std::string a = test::readFile(dir.file(fmt::format("joined.{}", ext)));
        CHECK(!a.empty());
        CHECK(a == test::readFile(dir.file(fmt::format("whole.{}", ext))));
    }
    // A missing frame is an error naming it, and no video is left.
    fs::remove(dir.file("frames/f_007.png"));
    auto r = moireIn(dir, "farm encode frames/f_%03d.png --frames 0..11 --fps 12 -o gap.mp4");
    CHECK(r.status == 3);
    CHECK(r.err.find("f_007.png") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("gap.mp4")));
}

TEST_CASE("an mp4 is the same file whatever the number of cores the encoder sees") {
    // A farm's join runs on whichever node Slurm gives it; the video it encodes must equal a
    // clip made anywhere. libx264 left to itself sizes its threads by the cores it sees.
    if (test::runCommand("command -v ffmpeg >/dev/null && command -v taskset >/dev/null").status !=
        0) {
        test::skip("ffmpeg or taskset is not installed");
        return;
    }
    test::TempDir dir("farm");
    dir.write("anim.moire", kScene);
    const std::string clip = "clip anim.moire --fps 12 --frames 0..11 -q --backend interp -o ";
    REQUIRE(moireIn(dir, clip + "all.mp4").status == 0);
    REQUIRE(moireIn(dir, clip + "one.mp4", "taskset -c 0").status == 0);
    CHECK(test::readFile(dir.file("one.mp4")) == test::readFile(dir.file("all.mp4")));
}

TEST_CASE("farm clip --plan prints the scripts and writes nothing") {
    test::TempDir dir("farm");
    dir.write("anim.moire", kScene);
    auto r = moireIn(dir, "farm clip anim.moire --fps 12 --frames 0..9 --shards 3 --workdir w "
                          "--partition p1 '--sbatch-arg=--time=5' -D 'gap=5' "
                          "-o out.mp4 --moire /opt/moire --plan");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK_FALSE(fs::exists(dir.file("w")));
    const std::string w = fs::canonical(dir.path()).string() + "/w";
    for (const char* name : {"shard.sh", "join.sh", "submit.sh"})
        CHECK(r.out.find(fmt::format("==> {}/{} <==", w, name)) != std::string::npos);
    // Ranges of 4, 3 and 3 frames, each a clip of the scene's copy in the work directory.
    for (const char* range : {"0..3", "4..6", "7..9"})
        CHECK(r.out.find(fmt::format(
                  "exec /opt/moire clip {}/scene.moire --fps 12 --from 0 --frames {} -D "
                  "gap=5 --depth 8 -o {}/frames/f_%09d.png -q",
                  w, range, w)) != std::string::npos);
    CHECK(r.out.find(fmt::format("/opt/moire farm encode {0}/frames/f_%09d.png --frames 0..9 "
                                 "--fps 12 -o {1}/out.mp4 -q",
                                 w, fs::canonical(dir.path()).string())) != std::string::npos);
    CHECK(r.out.find("--array=0-2") != std::string::npos);
    CHECK(r.out.find("--partition=p1 --time=5") != std::string::npos);
}

TEST_CASE("farm's commands take -q and -v, and their help ends with the exit statuses") {
    test::TempDir dir("farm");
    for (const char* verb : {"clip", "render"}) {
        CAPTURE(verb);
        auto r = moireIn(dir, fmt::format("farm {} --help", verb));
        CHECK(r.status == 0);
        CHECK(r.out.find("-q,--quiet") != std::string::npos);
        CHECK(r.out.find("-v,--verbose") != std::string::npos);
        CHECK(r.out.find("Exit status:") != std::string::npos);
        CHECK(r.out.find("docs/farm.md") != std::string::npos);
    }
    CHECK(moireIn(dir, "farm encode --help").out.find("Exit status:") != std::string::npos);
}

TEST_CASE("farm refuses what cannot work before submitting anything") {
    test::TempDir dir("farm");
    dir.write("anim.moire", kScene);
    const std::string base = "farm clip anim.moire --fps 12 --frames 4 --workdir w ";
    struct Case {
        std::string args, message;
        int status;
    };
    fs::create_directories(dir.file("full"));
    dir.write("full/x", "");
    for (const Case& c : std::vector<Case>{
             {base + "--shards 0 -o a.mp4", "--shards must be 1 or more", 2},
             {base + "--shards 2 --size 47x32 -o a.mp4", "even width and height", 2},
             {base + "--shards 2 -o a.png", "a video (.mp4, .webm, .gif) or numbered images", 2},
             {base + "--shards 2 -o a.mp4 --depth 16", "video frames are 8-bit", 2},
             {"farm clip anim.moire --fps 12 --frames 4 --workdir full --shards 2 -o a.mp4",
              "the work directory", 2},
             {"farm render anim.moire --workdir w --shards 2 -o a.xyz", "unknown format", 2},
         }) {
        CAPTURE(c.args);
        auto r = moireIn(dir, c.args);
        CHECK(r.status == c.status);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(r.err.find("moire: error: ") == 0);
    }
    // A scene with errors is reported as a clip of it would be.
    dir.write("bad.moire", "layer { family = nope }\n");
    auto bad = moireIn(dir, "farm clip bad.moire --fps 12 --frames 4 --workdir w --shards 2 "
                            "-o a.mp4");
    CHECK(bad.status == 1);
    CHECK(bad.err.find("bad.moire:1:") == 0);
    // Without sbatch the scripts are not submitted; --plan needs none.
    auto none = moireIn(dir, base + "--shards 2 -o a.mp4", "PATH=/nonexistent");
    CHECK(none.status == 4);
    CHECK(none.err.find("sbatch is not on PATH") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("w")));
}

TEST_CASE("farm through a stand-in sbatch: the joined video and posters are the local files") {
    // The interpreter, on both sides: no kernel to compile in each of the many runs.
    // The stand-in runs each array task, then the join, at once and in order, as Slurm would
    // when every shard succeeds; tests/farm runs the same on a real cluster.
    test::TempDir dir("farm");
    dir.write("anim.moire", kScene);
    fs::create_directories(dir.file("bin"));
    dir.write("bin/sbatch",
              "#!/bin/bash\n"
              "array='' out='' script=''\n"
              "for a; do case $a in --array=*) array=${a#--array=} ;;\n"
              "  --output=*) out=${a#--output=} ;; -*) ;; *) script=$a ;; esac; done\n"
              "if [[ -n $array ]]; then\n"
              "  for i in $(seq ${array%-*} ${array#*-}); do\n"
              "    SLURM_ARRAY_TASK_ID=$i bash \"$script\" >\"${out//%a/$i}\" 2>&1 || exit 1\n"
              "  done\n"
              "  echo 7\n"
              "else bash \"$script\" >\"$out\" 2>&1 || exit 1; echo 8; fi\n");
    fs::permissions(dir.file("bin/sbatch"), fs::perms::owner_all);
    const std::string path = "PATH='" + dir.file("bin") + "':$PATH";
    std::vector<std::pair<std::string, std::string>> requests = {
        {"farm render anim.moire --size 60x40 --time 0.25 --shards 4 --workdir w1 -o farm.png",
         "render anim.moire --size 60x40 --time 0.25 -o local.png"},
        {"farm render anim.moire --size 60x40 --shards 2 --workdir w2 -o farm.jpg",
         "render anim.moire --size 60x40 -o local.jpg"},
        {"farm render anim.moire --size 60x40 --depth 16 --dpi 300 --shards 2 --workdir w3 -o "
         "farm.tif",
         "render anim.moire --size 60x40 --depth 16 --dpi 300 -o local.tif"},
    };
    if (test::runCommand("command -v ffmpeg >/dev/null").status == 0)
        requests.push_back({"farm clip anim.moire --fps 12 --frames 10 --shards 3 --workdir w4 "
                            "-D gap=6 -o farm.mp4",
                            "clip anim.moire --fps 12 --frames 10 -D gap=6 -o local.mp4"});
    else
        test::skip("ffmpeg is not installed: no farmed video");
    for (const auto& [farmed, local] : requests) {
        CAPTURE(farmed);
        auto f = moireIn(dir, farmed + " --backend interp --wait", path);
        INFO(f.out, f.err);
        REQUIRE(f.status == 0);
        auto l = moireIn(dir, local + " --backend interp -q");
        REQUIRE(l.status == 0);
        const std::string ext = fs::path(local).extension().string();
        const std::string a = test::readFile(dir.file("farm" + ext));
        CHECK(!a.empty());
        CHECK(a == test::readFile(dir.file("local" + ext)));
    }
    // The pieces are gone once joined; the logs stay.
    CHECK_FALSE(fs::exists(dir.file("w1/tiles")));
    CHECK(fs::exists(dir.file("w1/logs/shard-3.log")));
}
