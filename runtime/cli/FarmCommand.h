// `moire farm`: a clip or a poster rendered as shards on a Slurm cluster (runtime/farm/,
// docs/farm.md). It writes the job scripts into a work directory every node shares and
// submits them with sbatch; Slurm does the scheduling. `farm encode` is the video join.
#pragma once

#include "compiler/Defines.h"
#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace moire::cli {

struct FarmArgs {
    enum class Mode { None, Clip, Render, Encode } mode = Mode::None;
    // The request, as `moire clip` and `moire render` take it.
    std::string scene;  // empty: the embedded default scene
    std::string output; // clip: a video or a numbered image name; render: an image
    std::string size;   // "WxH", empty: the scene's
    double fps = 0.0, from = 0.0, to = 0.0, time = 0.0;
    bool hasTo = false;
    std::string frames; // "N" or "A..B"
    std::string backend;
    int device = -1;
    std::string depth;
    int threads = 0;
    double dpi = 0.0;                   // render: recorded in the tiles, and so in the poster
    int compression = -1;               // render: the poster's PNG level (-1: render's default)
    std::vector<std::string> shardArgs; // more options for every shard's moire, as given
    std::string filter;                 // --filter point|mean for every shard; empty: the scene's
    Defines defines;
    // The farm.
    int shards = 0;
    std::string workdir;   // on the shared filesystem
    std::string partition; // empty: the cluster's default
    std::string moire;     // the moire binary as the nodes see it; empty: this one's path
    std::vector<std::string> sbatchArgs;
    bool plan = false; // print the scripts, write and submit nothing
    bool wait = false; // return when the join has finished
    Verbosity verbosity;
};

// Declares `farm` and its subcommands on `app` (-D is collected into `rawDefines`, which the
// shards are given as they were written).
CLI::App* addFarmCommand(CLI::App& app, FarmArgs& args, std::vector<std::string>& rawDefines);
int farm(const FarmArgs& args, const std::vector<std::string>& rawDefines);

} // namespace moire::cli
