#include "mcmc/mutations/walk_figures.h"

#include <sstream>

namespace lt {

std::string WalkFigures::text(const std::string& strategy) const {
    if (!walks.attempted) return {};
    std::ostringstream out;
    walks.print(out);
    return strategy + " walks:\n" + out.str();
}

std::optional<WalkOutcome>& walkRecord(Proposal& out) {
    if (out.figures) return static_cast<WalkFigures&>(*out.figures).walk;
    thread_local std::optional<WalkOutcome> unread;
    return unread;
}

RejectCause rejectCauseOf(WalkFailure f) {
    switch (f) {
    case WalkFailure::Occluded:
        return RejectCause::Occluded;
    case WalkFailure::NonReversible:
        return RejectCause::NotReversible;
    default:
        return RejectCause::WalkFailed;
    }
}

} // namespace lt
