// The SLURM job fuzz_collect collects (two points of crowd), shared with
// oovr-fuzz-seeds, which writes the task's real lines as seeds.
#pragma once

inline constexpr const char* kCollectSweep =
    "name = \"c\"\nscenes = [\"crowd\"]\nschemes = [\"baseline\", \"afr\"]\nresolutions = [\"64x48\"]\nframes = 4\n";
