// The time step's network on one rank of yade.mpy, as a space for the mode iteration of
// NetworkSpectrum.hpp (physics.md P18): the whole network's limit, computed by all ranks together.
//
// A rank holds the interactions of its own bodies, bridges to the neighbours' mirrored bodies
// ("ghosts") included, so its operator gives its own bodies' rows of the whole network's product
// exactly once the ghost entries of the input are its owners' (exchanged before every product).
// Dot products are over own rows, summed over the ranks in rank order: every rank runs the same
// iterations and finds the serial limit, up to rounding, whatever the split.
#pragma once
#include "viscbridge/distributed/GhostExchange.hpp"
#include "viscbridge/scene/NetworkOfScene.hpp"

namespace yade {

class NetworkOverRanks {
public:
	NetworkOverRanks(const Scene* scene, const NetworkOfScene& network);
	const viscbridge::NetworkOperator& op;

	std::size_t size() const { return op.size(); }
	bool        owns(std::size_t i) const { return own_[i] != 0; }
	void        apply(const viscbridge::VecX& y, viscbridge::VecX& Dy, viscbridge::VecX& Ky) const;
	void        diagonal(viscbridge::VecX& D, viscbridge::VecX& K) const;
	double      dot(const viscbridge::VecX& a, const viscbridge::VecX& b) const;
	double      sum(double v) const;
	double      max(double v) const;
	std::vector<std::pair<double, long>> largest(const std::vector<std::pair<double, long>>& mine, std::size_t count) const;
	// this rank's part of a vector, the ghosts' entries zero (they are their owners' to report)
	viscbridge::VecX ownPart(const viscbridge::VecX& y) const { return y.cwiseProduct(own_); }

private:
	const Scene*             scene_;
	viscbridge::VecX         own_; // 1 on the components of this rank's bodies
	mutable GhostExchange    exchange_;
	mutable viscbridge::VecX refreshed_;
};

} // namespace yade
