// The pieces `moire farm` hands to a batch scheduler, as plain data and shell text: how a
// clip's frames or a poster's pixels are cut into shards, and the three scripts (one Slurm
// array task per shard, one join that depends on them all, and the submission that links
// them). Nothing here runs anything, so every script can be printed (--plan) and tested
// without a cluster. docs/farm.md describes the scripts.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace moire::farm {

// Frames first..last of a clip, inclusive.
struct FrameShard {
    int64_t first = 0, last = 0;
};
// first..last cut into at most `shards` contiguous ranges, in order, whose lengths differ by
// at most one (the longer ones first); fewer ranges when there are fewer frames. shards >= 1.
std::vector<FrameShard> splitFrames(int64_t first, int64_t last, int shards);

// A window [x0, x1) x [y0, y1) of a width x height frame.
struct Region {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
// The grid of columns x rows = `shards` tiles (shards >= 1) whose tiles are nearest to
// square, row by row from the top left; the edges of column i are i * width / columns, so
// the tiles cover the frame exactly once. Fewer columns or rows when a side has too few
// pixels for them.
std::vector<Region> splitRegions(int width, int height, int shards);

// `word` quoted for a POSIX shell (unchanged when it needs no quoting).
std::string shellQuote(const std::string& word);
// The words quoted and joined by spaces: one shell command.
std::string shellCommand(const std::vector<std::string>& argv);

// What to submit: one command per array task, and the join to run after they all succeed.
struct FarmJob {
    std::string name;    // the jobs' names in squeue: <name>-shard, <name>-join
    std::string workdir; // absolute; on the filesystem every node shares
    std::string partition;
    std::vector<std::string> sbatchArgs;          // given to both sbatch calls, as they are
    std::vector<std::vector<std::string>> shards; // argv of array task i
    std::vector<std::vector<std::string>> join;   // commands of the join, in order
    bool wait = false; // the submission returns when the join has finished (sbatch --wait)
};

struct FarmScripts {
    std::string shard;  // shard.sh: the array task; runs shards[SLURM_ARRAY_TASK_ID]
    std::string join;   // join.sh: the join commands
    std::string submit; // submit.sh: sbatch --array, then sbatch --dependency=afterok
};
FarmScripts makeScripts(const FarmJob& job);

} // namespace moire::farm
