// What a person reads about a run: the engine's lines for the terminal, and the `text` of its
// progress and summary events, which the add-on and its command line show as they are. The
// pieces every command's lines share (progress, rejections, counts) and a seek's whole lines are
// worded here, once; each command's summary (main.cpp) is built from them.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "seek/GoalSearch.h"

namespace mwb {

/// 1234567 -> "1,234,567".
std::string with_commas(uint64_t n);

/// "sampled 3/10 worlds": a sampling or a refinement's progress (`verb`: "sampled", "refined").
std::string worlds_done_text(const char* verb, uint64_t done, uint64_t total);

/// "1 part", "6 parts": a goal's parts, boxes and poses together.
std::string parts_text(uint64_t count);

/// "8 rejected (5: the simulation did not finish within 120 s; 3: ...)", the commonest reasons
/// first, at most `shown` of them and a count for the rest; "" when nothing was rejected.
std::string rejections_text(uint64_t rejected, const std::map<std::string, uint64_t>& reasons, size_t shown = 2);

/// "best 5 of 6 parts (world 418), 3,120 worlds made (12 rejected), 2 meet all".
std::string seek_progress_text(const SeekStatus& status);

/// One line on how a seek ended: "Goal reached: 3 worlds meet all 6 parts (412, 415, 430);
/// 1,204 worlds made in 61.2 s", "Budget spent: best world 418 meets 5 of 6 parts; ..." or
/// "Cancelled: ...". `want`: how many worlds the seek was asked for.
std::string seek_outcome_text(const SeekOutcome& outcome, uint64_t want);

}  // namespace mwb
