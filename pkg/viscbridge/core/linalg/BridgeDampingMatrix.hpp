// The damping matrix of one bridge: D_c with D_c q = R for q = (v1, ω1, v2, ω2), R the bridge's
// resistance (ViscousBlock.hpp), written as four 6×6 blocks so that the implicit solver can assemble
// M + Δt Σ D_c (physics.md §4, P15) without evaluating the bridge once per unit vector.  YADE-free.
//
// With σ1 = +1, σ2 = −1, R_k = [r_k]× and N = [n]×:  dv = Σ_l σ_l (v_l − R_l ω_l),  s = −N Σ_l a_l ω_l,
// F = T dv + m12 s with T = cn nnᵀ + m11 (I − nnᵀ),  G = m21 (I − nnᵀ) dv + m22 s,
// force on side k σ_k F, torque a_k N G + σ_k R_k F.
#pragma once
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include <Eigen/Core>

namespace viscbridge {

struct BridgeDampingMatrix {
	Eigen::Matrix<double, 6, 6> block[2][2]; // block[k][l]: rows of side k, columns of side l
};

inline Eigen::Matrix3d crossMatrix(const Vec3& a)
{
	Eigen::Matrix3d m;
	m << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
	return m;
}

// Two spheres (r1 = r2 = 0): with N P = N and N² = −P the blocks reduce to
// σ_kσ_l T, −σ_k a_l m12 N, σ_l a_k m21 N and a_k a_l m22 P (a fifth of the general form's work).
inline BridgeDampingMatrix sphereBridgeDampingMatrix(const ViscousBlock& b)
{
	using Mat3              = Eigen::Matrix3d;
	const auto&  m          = b.resistance;
	const Mat3   nn         = b.n * b.n.transpose(), P = Mat3::Identity() - nn, N = crossMatrix(b.n);
	const Mat3   T          = b.cn * nn + m.m11 * P;
	const double sigma[2]   = { 1, -1 }, arm[2] = { b.a1, b.a2 };
	BridgeDampingMatrix out;
	for (int k = 0; k < 2; ++k)
		for (int l = 0; l < 2; ++l) {
			auto& B = out.block[k][l];
			B.topLeftCorner<3, 3>()     = (sigma[k] * sigma[l]) * T;
			B.topRightCorner<3, 3>()    = (-sigma[k] * arm[l] * m.m12) * N;
			B.bottomLeftCorner<3, 3>()  = (sigma[l] * arm[k] * m.m21) * N;
			B.bottomRightCorner<3, 3>() = (arm[k] * arm[l] * m.m22) * P;
		}
	return out;
}

inline BridgeDampingMatrix bridgeDampingMatrix(const ViscousBlock& b)
{
	if (!isAnchored(b)) return sphereBridgeDampingMatrix(b);
	using Mat3              = Eigen::Matrix3d;
	const auto&  m          = b.resistance;
	const Mat3   nn         = b.n * b.n.transpose(), P = Mat3::Identity() - nn, N = crossMatrix(b.n);
	const Mat3   T          = b.cn * nn + m.m11 * P;
	const double sigma[2]   = { 1, -1 }, arm[2] = { b.a1, b.a2 };
	const Mat3   R[2]       = { crossMatrix(b.r1), crossMatrix(b.r2) };
	BridgeDampingMatrix out;
	for (int l = 0; l < 2; ++l) {
		// the force F and torque-force G per unit velocity (columns v_l) and angular velocity (ω_l)
		const Mat3 dvOfW = -sigma[l] * R[l], sOfW = -arm[l] * N;
		const Mat3 Fv = sigma[l] * T, Gv = sigma[l] * m.m21 * P;
		const Mat3 Fw = T * dvOfW + m.m12 * sOfW, Gw = m.m21 * P * dvOfW + m.m22 * sOfW;
		for (int k = 0; k < 2; ++k) {
			auto& B = out.block[k][l];
			B.topLeftCorner<3, 3>()     = sigma[k] * Fv;
			B.topRightCorner<3, 3>()    = sigma[k] * Fw;
			B.bottomLeftCorner<3, 3>()  = arm[k] * N * Gv + sigma[k] * R[k] * Fv;
			B.bottomRightCorner<3, 3>() = arm[k] * N * Gw + sigma[k] * R[k] * Fw;
		}
	}
	return out;
}

} // namespace viscbridge
