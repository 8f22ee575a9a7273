#include "viscbridge/scene/NetworkOverRanks.hpp"
#include <algorithm>
#include <limits>

namespace yade {

namespace {
	viscbridge::VecX ownedComponents(const Scene* scene, const std::vector<Body::id_t>& ids)
	{
		const auto       own = distributed::ownership(scene);
		viscbridge::VecX mask(6 * static_cast<long>(ids.size()));
		for (std::size_t i = 0; i < ids.size(); ++i)
			mask.segment<6>(6 * i).setConstant(own.body(*(*scene->bodies)[ids[i]]) ? 1.0 : 0.0);
		return mask;
	}
}

NetworkOverRanks::NetworkOverRanks(const Scene* scene, const NetworkOfScene& network)
        : op(network.op)
        , scene_(scene)
        , own_(ownedComponents(scene, network.idOf))
        , exchange_(scene, network.idOf, ghostMask(scene, network.idOf))
{
}

void NetworkOverRanks::apply(const viscbridge::VecX& y, viscbridge::VecX& Dy, viscbridge::VecX& Ky) const
{
	refreshed_ = y;
	exchange_.refresh(refreshed_);
	op.apply(refreshed_, Dy, Ky);
	Dy = Dy.cwiseProduct(own_), Ky = Ky.cwiseProduct(own_); // the ghosts' rows are their owners'
}

void NetworkOverRanks::diagonal(viscbridge::VecX& D, viscbridge::VecX& K) const
{
	op.diagonal(D, K);
	D = D.cwiseProduct(own_), K = K.cwiseProduct(own_);
}

double NetworkOverRanks::dot(const viscbridge::VecX& a, const viscbridge::VecX& b) const { return distributed::sum(scene_, a.cwiseProduct(own_).dot(b)); }

double NetworkOverRanks::sum(double v) const { return distributed::sum(scene_, v); }

double NetworkOverRanks::max(double v) const
{
	const std::vector<double> all = distributed::allGather(scene_, { v });
	return *std::max_element(all.begin(), all.end());
}

std::vector<std::pair<double, long>> NetworkOverRanks::largest(const std::vector<std::pair<double, long>>& mine, std::size_t count) const
{
	// every rank sends `count` entries (padded), so that the gathered blocks line up
	std::vector<double> flat;
	for (std::size_t i = 0; i < count; ++i) {
		flat.push_back(i < mine.size() ? mine[i].first : -std::numeric_limits<double>::infinity());
		flat.push_back(i < mine.size() ? static_cast<double>(mine[i].second) : -1.0);
	}
	const std::vector<double>            all = distributed::allGather(scene_, flat);
	std::vector<std::pair<double, long>> out;
	for (std::size_t i = 0; i + 1 < all.size(); i += 2)
		if (all[i + 1] >= 0) out.push_back({ all[i], static_cast<long>(all[i + 1]) });
	return out;
}

} // namespace yade
