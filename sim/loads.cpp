#include "sim/loads.hpp"

#include "shell/quadrature.hpp"

namespace shellfrac::sim {

namespace {

// The distinct knot values of the domain: span boundaries.
std::vector<double> breaks(const nurbs::KnotVector& k) {
  std::vector<double> b{k.domain_begin()};
  for (double x : k.interior_breakpoints()) b.push_back(x);
  b.push_back(k.domain_end());
  return b;
}

}  // namespace

LoadSystem::LoadSystem(const scene::Model& model, const World& world) : applied_(model.loads.size(), Eigen::Vector3d::Zero()) {
  nurbs::SurfaceBasis basis;
  for (const scene::model::Load& load : model.loads) {
    const shell::ShellPatch& patch = world.shell(load.shell);
    const nurbs::NurbsSurface& surf = patch.reference();
    Active a{&load, {}, {}};
    auto add = [&](double u, double v, double weight) {
      surf.rational_basis(u, v, basis);
      Sample s;
      s.index.assign(basis.index.begin(), basis.index.begin() + basis.count);
      s.R.assign(basis.R.begin(), basis.R.begin() + basis.count);
      s.Ru.assign(basis.Ru.begin(), basis.Ru.begin() + basis.count);
      s.Rv.assign(basis.Rv.begin(), basis.Rv.begin() + basis.count);
      s.weight = weight;
      a.samples.push_back(std::move(s));
      return &a.samples.back();
    };
    const shell::GaussRule g = shell::gauss_legendre(model.shells[load.shell].quadrature.points_per_direction);
    const std::vector<double> bu = breaks(surf.knots_u()), bv = breaks(surf.knots_v());
    using Kind = scene::model::Load::Kind;
    if (load.kind == Kind::Pressure) {
      for (size_t i = 0; i + 1 < bu.size(); ++i)
        for (size_t j = 0; j + 1 < bv.size(); ++j)
          for (size_t a1 = 0; a1 < g.x.size(); ++a1)
            for (size_t a2 = 0; a2 < g.x.size(); ++a2) {
              const double hu = 0.5 * (bu[i + 1] - bu[i]), hv = 0.5 * (bv[j + 1] - bv[j]);
              add(bu[i] + hu * (1 + g.x[a1]), bv[j] + hv * (1 + g.x[a2]), g.w[a1] * g.w[a2] * hu * hv);
            }
    } else if (load.kind == Kind::Point) {
      add(load.at.x(), load.at.y(), 1.0);
    } else if (load.kind == Kind::Edge) {
      const bool along_v = load.edge < 2;  // u0, u1 run along v
      const double fixed = load.edge == 0   ? bu.front()
                           : load.edge == 1 ? bu.back()
                           : load.edge == 2 ? bv.front()
                                            : bv.back();
      const std::vector<double>& b = along_v ? bv : bu;
      for (size_t i = 0; i + 1 < b.size(); ++i)
        for (size_t q = 0; q < g.x.size(); ++q) {
          const double h = 0.5 * (b[i + 1] - b[i]), s = b[i] + h * (1 + g.x[q]);
          Sample* sp = add(along_v ? fixed : s, along_v ? s : fixed, 0.0);
          // Reference arc length |dX/ds| ds: a line load per unit length of the undeformed edge.
          Eigen::Vector3d tangent = Eigen::Vector3d::Zero();
          for (size_t k = 0; k < sp->index.size(); ++k)
            tangent += (along_v ? sp->Rv[k] : sp->Ru[k]) * patch.x[static_cast<size_t>(sp->index[k])];
          sp->weight = g.w[q] * h * tangent.norm();
        }
    } else {
      a.mass = patch.mass;
      for (size_t c = 0; c < patch.shear.x.size(); ++c) {
        const Eigen::Vector2d& uv = patch.shear_parameter(c);
        surf.rational_basis(uv.x(), uv.y(), basis);
        for (int k = 0; k < basis.count; ++k)
          a.mass[static_cast<size_t>(basis.index[static_cast<size_t>(k)])] += basis.R[static_cast<size_t>(k)] * patch.shear.mass[c];
      }
    }
    loads_.push_back(std::move(a));
  }
}

void LoadSystem::apply(World& world, double t) {
  using Kind = scene::model::Load::Kind;
  for (size_t i = 0; i < loads_.size(); ++i) {
    const Active& a = loads_[i];
    const scene::model::Load& load = *a.load;
    shell::ShellPatch& patch = world.shell(load.shell);
    const double factor = load.ramp.at(t);
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    if (load.kind == Kind::Body) {
      for (size_t k = 0; k < a.mass.size(); ++k) {
        const Eigen::Vector3d f = factor * a.mass[k] * load.vector;
        patch.force[k] += f;
        total += f;
      }
    } else {
      for (const Sample& s : a.samples) {
        Eigen::Vector3d traction = factor * s.weight * load.vector;
        if (load.kind == Kind::Pressure) {  // p a_1 x a_2 du dv on the current surface
          Eigen::Vector3d a1 = Eigen::Vector3d::Zero(), a2 = Eigen::Vector3d::Zero();
          for (size_t k = 0; k < s.index.size(); ++k) {
            a1 += s.Ru[k] * patch.x[static_cast<size_t>(s.index[k])];
            a2 += s.Rv[k] * patch.x[static_cast<size_t>(s.index[k])];
          }
          traction = factor * s.weight * load.pressure * a1.cross(a2);
        }
        for (size_t k = 0; k < s.index.size(); ++k) {
          const Eigen::Vector3d f = s.R[k] * traction;
          patch.force[static_cast<size_t>(s.index[k])] += f;
          total += f;
        }
      }
    }
    applied_[i] = total;
  }
}

}  // namespace shellfrac::sim
