#include "viscbridge/distributed/GhostExchange.hpp"
#include <core/State.hpp>

namespace yade {

Eigen::VectorXd ghostMask(const Scene* scene, const std::vector<Body::id_t>& ids)
{
	// as free on their owners: dynamic, with a mass, not blocked
	const auto      own  = distributed::ownership(scene);
	Eigen::VectorXd mask = Eigen::VectorXd::Zero(6 * static_cast<long>(ids.size()));
	for (size_t i = 0; i < ids.size(); ++i) {
		const Body& b = *(*scene->bodies)[ids[i]];
		if (own.body(b) || b.subdomain == 0 || !b.isDynamic() || !(b.state->mass > 0)) continue;
		for (int d = 0; d < 6; ++d)
			mask[6 * i + d] = (b.state->blockedDOFs & State::axisDOF(d % 3, d >= 3)) ? 0 : 1;
	}
	return mask;
}

GhostExchange::GhostExchange(const Scene* scene, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& ghosts)
        : scene_(scene)
        , halo_(distributed::halo(scene))
        , ghosts_(ghosts)
{
	std::vector<int> index(scene->bodies->size(), -1);
	for (size_t i = 0; i < ids.size(); ++i)
		index[ids[i]] = static_cast<int>(i);
	auto at = [&](const std::vector<Body::id_t>& list) {
		std::vector<int> out;
		for (const Body::id_t id : list)
			out.push_back(id >= 0 && static_cast<size_t>(id) < index.size() ? index[id] : -1);
		return out;
	};
	for (size_t j = 0; j < halo_.ranks.size(); ++j) {
		sendAt_.push_back(at(halo_.sent[j]));
		receiveAt_.push_back(at(halo_.received[j]));
		send_.emplace_back(6 * halo_.sent[j].size(), 0.0);
		received_.emplace_back(6 * halo_.received[j].size(), 0.0);
	}
}

void GhostExchange::refresh(Eigen::VectorXd& v)
{
	for (size_t j = 0; j < sendAt_.size(); ++j)
		for (size_t k = 0; k < sendAt_[j].size(); ++k) {
			const int i = sendAt_[j][k];
			for (int d = 0; d < 6; ++d) // a body without degrees of freedom here has none on its neighbours either
				send_[j][6 * k + d] = i >= 0 ? v[6 * i + d] : 0.0;
		}
	distributed::exchange(scene_, halo_, send_, received_);
	for (size_t j = 0; j < receiveAt_.size(); ++j)
		for (size_t k = 0; k < receiveAt_[j].size(); ++k) {
			const int i = receiveAt_[j][k];
			if (i < 0) continue;
			for (int d = 0; d < 6; ++d)
				if (ghosts_[6 * i + d] != 0) v[6 * i + d] = received_[j][6 * k + d];
		}
}

} // namespace yade
