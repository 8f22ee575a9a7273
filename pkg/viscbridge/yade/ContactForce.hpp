// ContactForce: what a wet contact exerts in one step, kept by the law for ViscBridgeForceSum, which
// adds it to the bodies in the order of (lowerId, higherId) (docs/architecture.md, "Bit-identical on
// any number of threads"); the same list gives OrderedWetContacts the step's contacts without a scan.
#pragma once
#include <core/Body.hpp>
#include <core/Interaction.hpp>
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace yade {

struct ContactForce {
	Interaction* interaction;
	Body::id_t   id1, id2;
	Vector3r   force1, torque1, torque2; // on body 1; body 2 takes −force1 and torque2
	// the order of the sums: by the smaller id, then the larger
	size_t lowerId() const { return static_cast<size_t>(std::min(id1, id2)); }
	size_t higherId() const { return static_cast<size_t>(std::max(id1, id2)); }
};

// The order of contacts every sum over them follows: (smaller id, larger id) as one number.
inline std::uint64_t contactOrderKey(Body::id_t a, Body::id_t b)
{
	return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint64_t>(std::max(a, b));
}
// Contacts with their keys, in that order (OrderedWetContacts).
using OrderedContacts = std::vector<std::pair<std::uint64_t, Interaction*>>;

} // namespace yade
