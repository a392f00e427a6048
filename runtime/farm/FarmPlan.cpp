#include "runtime/farm/FarmPlan.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace moire::farm {

std::vector<FrameShard> splitFrames(int64_t first, int64_t last, int shards) {
    const int64_t count = last - first + 1;
    const int64_t n = std::clamp<int64_t>(shards, 1, std::max<int64_t>(count, 1));
    std::vector<FrameShard> out;
    int64_t at = first;
    for (int64_t i = 0; i < n; ++i) {
        int64_t len = count / n + (i < count % n ? 1 : 0);
        out.push_back({at, at + len - 1});
        at += len;
    }
    return out;
}

std::vector<Region> splitRegions(int width, int height, int shards) {
    // Of the factorisations columns x rows = shards that fit the frame, the one whose tiles
    // have the aspect ratio nearest to 1 (in log terms, so 2:1 and 1:2 are as far).
    int bestCols = 1, bestRows = 1;
    double bestSkew = INFINITY;
    for (int cols = 1; cols <= shards; ++cols) {
        if (shards % cols != 0) continue;
        int rows = shards / cols;
        if (cols > width || rows > height) continue;
        double skew = std::fabs(
            std::log((static_cast<double>(width) / cols) / (static_cast<double>(height) / rows)));
        if (skew < bestSkew) bestSkew = skew, bestCols = cols, bestRows = rows;
    }
    auto edge = [](int size, int parts, int i) {
        return static_cast<int>(static_cast<int64_t>(size) * i / parts);
    };
    std::vector<Region> out;
    for (int r = 0; r < bestRows; ++r)
        for (int c = 0; c < bestCols; ++c)
            out.push_back({edge(width, bestCols, c), edge(height, bestRows, r),
                           edge(width, bestCols, c + 1), edge(height, bestRows, r + 1)});
    return out;
}

std::string shellQuote(const std::string& word) {
    const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char c) {
        return std::isalnum(c) ||
               std::string_view("%+,-./:=@_").find(static_cast<char>(c)) != std::string_view::npos;
    });
    if (plain) return word;
    std::string out = "'";
    for (char c : word) {
        if (c == '\'')
            out += "'\\''";
        else
            out += c;
    }
    return out + "'";
}

std::string shellCommand(const std::vector<std::string>& argv) {
    std::string out;
    for (const std::string& a : argv) {
        if (!out.empty()) out += ' ';
        out += shellQuote(a);
    }
    return out;
}

FarmScripts makeScripts(const FarmJob& job) {
    FarmScripts s;
    const std::string dir = shellQuote(job.workdir);
    s.shard = fmt::format("#!/bin/bash\n"
                          "# {}: one shard; Slurm runs it once per array task, choosing the\n"
                          "# shard by SLURM_ARRAY_TASK_ID.\n"
                          "set -euo pipefail\n"
                          "case \"${{SLURM_ARRAY_TASK_ID:?run this with sbatch --array}}\" in\n",
                          job.name);
    for (size_t i = 0; i < job.shards.size(); ++i)
        s.shard += fmt::format("{}) exec {} ;;\n", i, shellCommand(job.shards[i]));
    s.shard += "*) echo \"no shard $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\nesac\n";

    s.join = fmt::format("#!/bin/bash\n"
                         "# {}: joins the shards once every one has succeeded.\n"
                         "set -euo pipefail\n",
                         job.name);
    for (const std::vector<std::string>& command : job.join) s.join += shellCommand(command) + "\n";
    // The mark that the join got to its end: sbatch --wait exits 0 for a join that Slurm
    // cancelled because a shard failed, so the submission looks for this instead.
    s.join += fmt::format("touch {}/joined\n", dir);

    // Options both sbatch calls take: where to run, and whatever the user added.
    std::string common;
    if (!job.partition.empty()) common += " " + shellQuote("--partition=" + job.partition);
    for (const std::string& a : job.sbatchArgs) common += " " + shellQuote(a);
    const std::string shardName = shellQuote(job.name + "-shard");
    const std::string joinName = shellQuote(job.name + "-join");
    s.submit = fmt::format(
        "#!/bin/bash\n"
        "# {0}: submits the {1} shards as one Slurm job array, then the join, which starts\n"
        "# only when every shard has succeeded (and is cancelled if one fails).\n"
        "set -euo pipefail\n"
        "cd {2}\n"
        "rm -f {2}/joined\n"
        "array=$(sbatch --parsable --job-name={3} --array=0-{4} --output={2}/logs/shard-%a.log"
        "{5} {2}/shard.sh)\n"
        "array=${{array%%;*}}\n"
        "echo \"moire farm: shards: job array $array ({1} tasks)\"\n"
        "if ! join=$(sbatch --parsable --job-name={6} --dependency=afterok:$array "
        "--kill-on-invalid-dep=yes --output={2}/logs/join.log{5}{7} {2}/join.sh){9}; then\n"
        "  echo \"moire farm: the join did not succeed: see {2}/logs\" >&2\n"
        "  exit 1\n"
        "fi\n"
        "echo \"moire farm: join: job ${{join%%;*}}{8}\"\n",
        job.name, job.shards.size(), dir, shardName, job.shards.size() - 1, common, joinName,
        job.wait ? " --wait" : "", job.wait ? " finished" : " (after the shards)",
        job.wait ? fmt::format(" || [[ ! -e {}/joined ]]", dir) : "");
    return s;
}

} // namespace moire::farm
