// The entries of a vector over the bodies of one rank of yade.mpy that belong to other workers'
// bodies ("ghosts", mpy's mirrors), refreshed from their owners by a halo exchange along mpy's own
// intersection lists: for the collective solves over ranks (implicit CG, the time step's mode).
#pragma once
#include <Eigen/Core>
#include <core/Scene.hpp>
#include "viscbridge/distributed/Distributed.hpp"
#include <vector>

namespace yade {

// 1 on the free components of the bodies (listed by `ids`, 6 entries each) other workers own, 0
// elsewhere.  The master's bodies are boundary conditions, as in mpy, which never sends their states.
Eigen::VectorXd ghostMask(const Scene* scene, const std::vector<Body::id_t>& ids);

// Refreshes the ghost entries of a vector from their owners (who send their own entries).  Collective.
class GhostExchange {
public:
	GhostExchange(const Scene* scene, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& ghosts);
	void refresh(Eigen::VectorXd& v);

private:
	const Scene*                     scene_;
	distributed::Halo                halo_;
	Eigen::VectorXd                  ghosts_;
	std::vector<std::vector<int>>    sendAt_, receiveAt_;
	std::vector<std::vector<double>> send_, received_;
};

} // namespace yade
