#include "mgelastic/validation/lame_sphere.hpp"

#include <array>
#include <cmath>

#include "mgelastic/core/error.hpp"
#include "mgelastic/validation/static_solve.hpp"

namespace mgelastic::validation {
namespace {

nlohmann::json scene_document(const std::string& engine, const LameSphere& s, int resolution,
                              double h) {
  const double b = s.outer_radius, patch = 2.2 * h;
  nlohmann::json constraints = nlohmann::json::array();
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      std::array<double, 3> center{0, 0, 0};
      center[axis] = sign * b;
      constraints.push_back(
          {{"region", {{"box", {{"center", center}, {"size", {patch, patch, patch}}}}}}});
    }
  return {{"engine", engine},
          {"geometry",
           {{"difference",
             {{{"sphere", {{"center", {0, 0, 0}}, {"radius", b}}}},
              {{"sphere", {{"center", {0, 0, 0}}, {"radius", s.inner_radius}}}}}}}},
          {"grid", {{"resolution", resolution}}},
          {"tet", {{"resolution", resolution}, {"tolerance", 1e-11}}},
          {"material",
           {{"youngs_modulus", s.youngs_modulus},
            {"poisson_ratio", s.poisson_ratio},
            {"density", 1000}}},
          {"constraints", constraints},
          {"loads",
           {{"gravity", {0, 0, 0}},
            {"pressures",
             {{{"region",
                {{"sphere", {{"center", {0, 0, 0}}, {"radius", 0.5 * (s.inner_radius + b)}}}}},
               {"pressure", s.pressure}}}}}}};
}

// Inside a patch, or within one cell of it.
bool near_patch(const Eigen::Vector3d& x, double b, double h) {
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      c[axis] = sign * b;
      if (((x - c).cwiseAbs().array() <= 1.1 * h + h).all()) return true;
    }
  return false;
}

struct RadialMeans {
  double inner = 0, inner_exact = 0, outer = 0, outer_exact = 0;
};

// Means of the numerical and analytic u_r over the inner and outer surface vertices.
RadialMeans radial_means(const LameSphere& s, const Eigen::MatrixX3d& rest,
                         const Eigen::MatrixX3d& displacement, double h) {
  RadialMeans m;
  int inner = 0, outer = 0;
  const double middle = 0.5 * (s.inner_radius + s.outer_radius);
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Eigen::Vector3d x = rest.row(v).transpose();
    if (near_patch(x, s.outer_radius, h)) continue;
    const double r = x.norm();
    const double ur = displacement.row(v).dot(x.transpose()) / r;
    if (r < middle) {
      m.inner += ur, m.inner_exact += s.radial_displacement(r), ++inner;
    } else {
      m.outer += ur, m.outer_exact += s.radial_displacement(r), ++outer;
    }
  }
  if (inner == 0 || outer == 0) throw Error("lame_sphere: no surface vertex near one of the radii");
  m.inner /= inner, m.inner_exact /= inner, m.outer /= outer, m.outer_exact /= outer;
  return m;
}

}  // namespace

double LameSphere::radial_displacement(double r) const {
  const double a3 = std::pow(inner_radius, 3), b3 = std::pow(outer_radius, 3);
  const double A = pressure * a3 * (1 - 2 * poisson_ratio) / (youngs_modulus * (b3 - a3));
  const double B = pressure * a3 * b3 * (1 + poisson_ratio) / (2 * youngs_modulus * (b3 - a3));
  return A * r + B / (r * r);
}

std::vector<ConvergenceSeries> lame_sphere_study(const std::string& engine,
                                                 const LameSphere& sphere,
                                                 const std::vector<int>& resolutions) {
  ConvergenceSeries inner{"lame_sphere", engine, "mean u_r at r = a", "m", sphere.poisson_ratio};
  ConvergenceSeries outer{"lame_sphere", engine, "mean u_r at r = b", "m", sphere.poisson_ratio};
  const DisplacementField exact = [sphere](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    const double r = x.norm();
    return r > 0 ? Eigen::Vector3d(sphere.radial_displacement(r) / r * x) : Eigen::Vector3d::Zero();
  };
  for (int n : resolutions) {
    const double h = 2 * sphere.outer_radius / n;
    const nlohmann::json document = scene_document(engine, sphere, n, h);
    Eigen::MatrixX3d rest, displacement;
    ConvergenceRow row{n, h};
    if (engine == "grid") {
      const GridStatic run = solve_grid_static(document, exact);
      rest = run.setup.surface.vertices;
      displacement.resize(rest.rows(), 3);
      for (Eigen::Index v = 0; v < rest.rows(); ++v)
        displacement.row(v) = grid_displacement(run, rest.row(v).transpose()).transpose();
      row.unknowns = run.unknowns, row.converged = run.converged, row.seconds = run.seconds;
    } else {
      const TetStatic run = solve_tet_static(document, exact);
      tet_surface_displacement(run, rest, displacement);
      row.h = run.setup.cell_size;
      row.unknowns = run.unknowns, row.converged = run.converged, row.seconds = run.seconds;
    }
    const RadialMeans m = radial_means(sphere, rest, displacement, row.h);
    ConvergenceRow a = row, b = row;
    a.value = m.inner, a.reference = m.inner_exact;
    b.value = m.outer, b.reference = m.outer_exact;
    inner.rows.push_back(a);
    outer.rows.push_back(b);
  }
  const std::string note =
      "whole sphere a = " + std::to_string(sphere.inner_radius) +
      ", b = " + std::to_string(sphere.outer_radius) +
      "; six outer patches held at the analytic displacement (no roller constraints); reference: "
      "analytic u_r at each surface vertex's rest radius, averaged";
  for (ConvergenceSeries* s : {&inner, &outer}) {
    s->note = note;
    s->finish();
  }
  return {inner, outer};
}

}  // namespace mgelastic::validation
