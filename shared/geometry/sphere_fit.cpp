// sphere_fit.cpp — least-squares sphere and plane (see sphere_fit.hpp), solved with Eigen.
#include "geometry/sphere_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

void summarise(const std::vector<double>& r, double& rms, double& max_abs) {
  double ss = 0.0;
  max_abs = 0.0;
  for (double x : r) {
    ss += x * x;
    max_abs = std::max(max_abs, std::abs(x));
  }
  rms = r.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(r.size()));
}

Eigen::Vector3d centroid(const std::vector<Vec3>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Vec3& p : pts) c += Eigen::Vector3d(p[0], p[1], p[2]);
  return c / static_cast<double>(pts.size());
}

}  // namespace

SphereFit fit_sphere(const std::vector<Vec3>& points) {
  SphereFit out;
  const int n = static_cast<int>(points.size());
  if (n < 4) {
    out.error = "a sphere needs at least 4 points, got " + std::to_string(n);
    return out;
  }
  for (const Vec3& p : points) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      out.error = "a point is not a finite number";
      return out;
    }
  }
  // Algebraic fit about the centroid (conditioning): |q|² = 2 c·q + k, q = p − m.
  const Eigen::Vector3d m = centroid(points);
  Eigen::MatrixXd a(n, 4);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) - m;
    a.row(i) << 2.0 * q.x(), 2.0 * q.y(), 2.0 * q.z(), 1.0;
    b(i) = q.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 4) {
    out.error = "the points lie on one plane or line: no unique sphere";
    return out;
  }
  const Eigen::Vector4d s = qr.solve(b);
  Eigen::Vector3d c = s.head<3>();
  const double r2 = s(3) + c.squaredNorm();
  double r = r2 > 0.0 ? std::sqrt(r2) : 0.0;

  // Gauss–Newton on f_i = |q_i − c| − r.
  Eigen::MatrixXd j(n, 4);
  Eigen::VectorXd f(n);
  for (int it = 0; it < 50; ++it) {
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) - m - c;
      const double len = d.norm();
      const Eigen::Vector3d u = len > 0.0 ? Eigen::Vector3d(d / len) : Eigen::Vector3d::Zero();
      j.row(i) << -u.x(), -u.y(), -u.z(), -1.0;
      f(i) = len - r;
    }
    const Eigen::Vector4d step = j.colPivHouseholderQr().solve(-f);
    c += step.head<3>();
    r += step(3);
    out.iterations = it + 1;
    if (step.norm() < 1e-12) break;
  }
  out.centre = {c.x() + m.x(), c.y() + m.y(), c.z() + m.z()};
  out.radius = r;
  out.residuals.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.residuals[static_cast<std::size_t>(i)] = norm(points[static_cast<std::size_t>(i)] - out.centre) - r;
  summarise(out.residuals, out.rms, out.max_abs);
  return out;
}

PlaneFit fit_plane(const std::vector<Vec3>& points) {
  PlaneFit out;
  if (points.size() < 3) {
    out.error = "a plane needs at least 3 points, got " + std::to_string(points.size());
    return out;
  }
  const Eigen::Vector3d m = centroid(points);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) {
    const Eigen::Vector3d q = Eigen::Vector3d(p[0], p[1], p[2]) - m;
    scatter += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);  // eigenvalues ascending
  const Eigen::Vector3d ev = eig.eigenvalues();
  if (!(ev(1) > 1e-12 * ev(2))) {  // also rejects coincident points (ev(2) = 0)
    out.error = "the points lie on one line: no unique plane";
    return out;
  }
  Eigen::Vector3d nrm = eig.eigenvectors().col(0).normalized();
  if (nrm.z() < 0.0) nrm = -nrm;
  out.point = {m.x(), m.y(), m.z()};
  out.normal = {nrm.x(), nrm.y(), nrm.z()};
  out.residuals.reserve(points.size());
  for (const Vec3& p : points) out.residuals.push_back(dot(p - out.point, out.normal));
  summarise(out.residuals, out.rms, out.max_abs);
  return out;
}

}  // namespace pcnc
