// The one check-and-restore of ViscBridge's YADE classes: an attribute set from Python (or read from
// a saved scene) is checked in postLoad(); a rejected value raises ValueError and leaves every checked
// attribute as it was before the assignment.
//
//     auto checked() { return std::tie(iterPeriod, energyMargin); }        // the class's checked attributes
//     ctor:      rollback.keep(checked());                                // the defaults are the first valid set
//     postLoad:  rollback.check(checked(), [&] { requireInRange(...); }); // throws after restoring
#pragma once
#include <tuple>

namespace yade {

template <class... T> class AttributeRollback {
	std::tuple<T...> lastValid;

public:
	// Remember the current values as the last valid ones.
	template <class Refs> void keep(const Refs& current) { lastValid = current; }
	// Whether the attributes differ from the last valid values (an assignment is being checked).
	template <class Refs> bool differs(const Refs& current) const { return lastValid != current; }
	// Run `validate`; if it throws, put the last valid values back and rethrow, else keep the new ones.
	template <class Refs, class Validate> void check(Refs current, Validate&& validate)
	{
		try {
			validate();
		} catch (...) {
			current = lastValid;
			throw;
		}
		lastValid = current;
	}
};

} // namespace yade
