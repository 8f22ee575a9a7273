// A symmetric matrix of 6×6 blocks (one block row per body: its velocity and angular velocity), the
// form in which the implicit solver assembles M + Δt D for its preconditioners.  YADE-free.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <utility>
#include <vector>

namespace viscbridge {

using Mat6  = Eigen::Matrix<double, 6, 6>;
using VecXd = Eigen::VectorXd;
using MatXd = Eigen::MatrixXd;

// The diagonal blocks and, for each pair (i, j) with i < j, the block in row i and column j (the one
// in row j and column i is its transpose).
struct BlockMatrix6 {
	std::vector<Mat6>                diagonal;
	std::vector<std::pair<int, int>> pairs;
	std::vector<Mat6>                upper;

	int size() const { return static_cast<int>(diagonal.size()); }

	// y = A x (x, y of length 6·size()).
	void multiply(const VecXd& x, VecXd& y) const
	{
		y.resize(6 * size());
		for (int i = 0; i < size(); ++i)
			y.segment<6>(6 * i) = diagonal[i] * x.segment<6>(6 * i);
		for (size_t p = 0; p < pairs.size(); ++p) {
			const auto [i, j] = pairs[p];
			y.segment<6>(6 * i) += upper[p] * x.segment<6>(6 * j);
			y.segment<6>(6 * j) += upper[p].transpose() * x.segment<6>(6 * i);
		}
	}
};

} // namespace viscbridge
