#include "RunWords.h"

#include <algorithm>
#include <sstream>
#include <utility>
#include <vector>

namespace mwb {

std::string with_commas(uint64_t n) {
    const std::string digits = std::to_string(n);
    std::string out;
    for (size_t k = 0; k < digits.size(); ++k) {
        if (k && (digits.size() - k) % 3 == 0) out += ',';
        out += digits[k];
    }
    return out;
}

std::string worlds_done_text(const char* verb, uint64_t done, uint64_t total) {
    return std::string(verb) + " " + std::to_string(done) + "/" + std::to_string(total) + " worlds";
}

std::string parts_text(uint64_t count) {
    return count == 1 ? "1 part" : with_commas(count) + " parts";
}

std::string rejections_text(uint64_t rejected, const std::map<std::string, uint64_t>& reasons, size_t shown) {
    if (rejected == 0) return "";
    std::vector<std::pair<std::string, uint64_t>> commonest(reasons.begin(), reasons.end());
    std::stable_sort(commonest.begin(), commonest.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    std::ostringstream text;
    text << with_commas(rejected) << " rejected";
    if (commonest.empty()) return text.str();
    text << " (";
    for (size_t k = 0; k < commonest.size() && k < shown; ++k)
        text << (k ? "; " : "") << with_commas(commonest[k].second) << ": " << commonest[k].first;
    if (commonest.size() > shown) {
        uint64_t others = 0;
        for (size_t k = shown; k < commonest.size(); ++k) others += commonest[k].second;
        const size_t kinds = commonest.size() - shown;
        text << "; " << with_commas(others) << " for "
             << (kinds == 1 ? std::string("another reason") : std::to_string(kinds) + " other reasons");
    }
    text << ")";
    return text.str();
}

std::string seek_progress_text(const SeekStatus& status) {
    std::ostringstream text;
    text << "best " << status.best_boxes_met << " of " << parts_text(status.box_count) << " (world "
         << status.best_world << "), " << with_commas(status.worlds_made) << " worlds made";
    if (status.worlds_rejected) text << " (" << with_commas(status.worlds_rejected) << " rejected)";
    if (status.worlds_meeting_goal) text << ", " << with_commas(status.worlds_meeting_goal) << " meet all";
    return text.str();
}

namespace {

// "412, 415, 430", at most `limit` of them and "and N more".
std::string world_list(const std::vector<uint64_t>& worlds, size_t limit = 8) {
    std::ostringstream text;
    for (size_t k = 0; k < worlds.size() && k < limit; ++k) text << (k ? ", " : "") << worlds[k];
    if (worlds.size() > limit) text << " and " << worlds.size() - limit << " more";
    return text.str();
}

}  // namespace

std::string seek_outcome_text(const SeekOutcome& outcome, uint64_t want) {
    std::ostringstream made;
    made.precision(1);
    made << std::fixed << with_commas(outcome.worlds_made) << " worlds made in " << outcome.seconds << " s";
    const std::string lost = rejections_text(outcome.worlds_rejected, outcome.reject_reasons);
    if (!lost.empty()) made << ", " << lost;

    const size_t found = outcome.found.size();
    const std::string meet = std::to_string(found) + (found == 1 ? " world meets " : " worlds meet ") +
                             (outcome.box_count == 1 ? std::string("the goal")
                                                     : "all " + std::to_string(outcome.box_count) + " parts");
    std::ostringstream text;
    if (outcome.reached) {
        text << "Goal reached: " << meet << " (" << world_list(outcome.found) << ")";
    } else {
        text << (outcome.cancelled ? "Cancelled: " : "Budget spent: ");
        if (found > 0)
            text << meet << " (" << world_list(outcome.found) << ") of " << want << " wanted";
        else
            text << "best world " << outcome.best_world << " meets " << outcome.best_boxes_met << " of "
                 << parts_text(outcome.box_count);
    }
    text << "; " << made.str();
    return text.str();
}

}  // namespace mwb
