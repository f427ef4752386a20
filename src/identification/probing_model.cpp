#include "probing_model.hpp"

#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal::detail {

std::vector<std::size_t> parameter_indices(const Machine& m, const std::vector<std::string>& names,
                                           const std::string& option) {
  std::vector<std::size_t> out;
  const auto params = m.parameters();
  auto add = [&](std::size_t i) {
    if (std::find(out.begin(), out.end(), i) == out.end()) out.push_back(i);
  };
  for (const auto& name : names) {
    if (const auto i = m.parameter_index(name)) {
      add(*i);
      continue;
    }
    const auto err = ErrorName::parse(name);
    bool found = false;
    if (err)
      for (std::size_t i = 0; i < params.size(); ++i)
        if (params[i].error == *err) add(i), found = true;
    if (!found)
      throw InputError({option, 0, name}, "unknown parameter or error '" + printable(name) + "'" + name_hint(m, name) +
                                              " (" + parameter_naming(m) + ")");
  }
  return out;
}

ProbingModel::ProbingModel(const Machine& base, const ProbingPlan& plan, std::vector<std::size_t> parameters,
                           const std::vector<ScaleBar>& scale_bars, bool pretravel, double sigma_ball,
                           double sigma_facet, double sigma_scale_bar, double sigma_ballbar, double sigma_laser)
    : base_(base),
      plan_(plan),
      params_(std::move(parameters)),
      pretravel_(pretravel),
      sb_(sigma_ball),
      sf_(sigma_facet),
      ss_(sigma_scale_bar),
      sbb_(sigma_ballbar),
      sl_(sigma_laser) {
  for (double s : {sb_, sf_, ss_, sbb_, sl_})
    if (!(s > 0) || !std::isfinite(s))
      throw InputError({"sigma", 0, ""}, fmt::format("expected a standard deviation > 0 mm, found {:g}", s));
  n_ = params_.size();
  col_.assign(plan_.features.size(), 0);
  std::vector<bool> used(plan_.features.size(), false);
  for (const auto& r : plan_.records) used[r.feature] = true;
  for (std::size_t f = 0; f < plan_.features.size(); ++f) {
    if (!used[f]) continue;
    col_[f] = n_;
    n_ += unknowns_of(plan_.features[f].kind);
  }
  for (const auto& sb : scale_bars) {
    const auto a = plan_.feature_index(sb.ball_a), b = plan_.feature_index(sb.ball_b);
    for (const auto& [id, idx] : {std::pair{sb.ball_a, a}, std::pair{sb.ball_b, b}})
      if (!idx || plan_.features[*idx].kind != ProbeFeature::Kind::Ball)
        throw InputError({sb.source, 0, id},
                         "expected a ball of the measurements, found no ball '" + printable(id) + "'");
    if (*a == *b) throw InputError({sb.source, 0, sb.ball_a}, "a scale bar needs two different balls");
    for (const auto& [id, idx] : {std::pair{sb.ball_a, *a}, std::pair{sb.ball_b, *b}})
      if (!used[idx])
        throw InputError({sb.source, 0, id},
                         "ball '" + printable(id) + "' of the scale bar is never probed in these measurements");
    bars_.push_back({*a, *b, sb.length});
  }
  if (pretravel_) {
    bool facet = false;
    for (const auto& r : plan_.records) facet = facet || plan_.features[r.feature].kind == ProbeFeature::Kind::Facet;
    if (!facet)
      throw InputError({"pre-travel", 0, ""}, "pre-travel is estimated from facet touches; the measurements have none");
    pre_col_ = n_++;
  }
  m_ = plan_.residual_count() + bars_.size();
}

std::size_t ProbingModel::block_size(std::size_t b) const {
  if (b >= plan_.records.size()) return 1;
  return readings_of(plan_.features[plan_.records[b].feature].kind);
}
ProbeFeature::Kind ProbingModel::block_kind(std::size_t b) const { return plan_.features[plan_.records[b].feature].kind; }
bool ProbingModel::is_ball_block(std::size_t b) const {
  return b < plan_.records.size() && plan_.features[plan_.records[b].feature].kind == ProbeFeature::Kind::Ball;
}
bool ProbingModel::is_facet_block(std::size_t b) const {
  return b < plan_.records.size() && plan_.features[plan_.records[b].feature].kind == ProbeFeature::Kind::Facet;
}
double ProbingModel::sigma(std::size_t b) const {
  if (b >= plan_.records.size()) return ss_;
  switch (block_kind(b)) {
    case ProbeFeature::Kind::Ball: return sb_;
    case ProbeFeature::Kind::Facet: return sf_;
    case ProbeFeature::Kind::Ballbar: return sbb_;
    case ProbeFeature::Kind::Laser: return sl_;
  }
  return ss_;
}

std::vector<std::string> ProbingModel::names() const {
  std::vector<std::string> out(n_);
  const auto params = base_.parameters();
  for (std::size_t i = 0; i < params_.size(); ++i) out[i] = params[params_[i]].name;
  std::vector<bool> used(plan_.features.size(), false);
  for (const auto& r : plan_.records) used[r.feature] = true;
  for (std::size_t f = 0; f < plan_.features.size(); ++f) {
    if (!used[f]) continue;
    const auto& feat = plan_.features[f];
    if (feat.kind == ProbeFeature::Kind::Ball)
      for (int c = 0; c < 3; ++c) out[col_[f] + static_cast<std::size_t>(c)] = fmt::format("ball {} {}", feat.id, "xyz"[c]);
    if (feat.kind == ProbeFeature::Kind::Facet) out[col_[f]] = "facet " + feat.id;
    if (feat.kind == ProbeFeature::Kind::Ballbar) {
      const int k = ballbar_plane(feat);
      out[col_[f]] = fmt::format("ballbar {} {}", feat.id, "xyz"[(k + 1) % 3]);
      out[col_[f] + 1] = fmt::format("ballbar {} {}", feat.id, "xyz"[(k + 2) % 3]);
      out[col_[f] + 2] = "ballbar " + feat.id + " length offset";
    }
    if (feat.kind == ProbeFeature::Kind::Laser) out[col_[f]] = "laser " + feat.id + " offset";
  }
  if (pretravel_) out[pre_col_] = "pre-travel";
  return out;
}

void ProbingModel::put_artefact(std::size_t f, const ArtefactState& a, double* x) const {
  const auto kind = plan_.features[f].kind;
  const std::size_t c0 = col_[f];
  if (kind == ProbeFeature::Kind::Ball)
    for (std::size_t c = 0; c < 3; ++c) x[c0 + c] = a.ball[f][static_cast<Eigen::Index>(c)];
  if (kind == ProbeFeature::Kind::Facet || kind == ProbeFeature::Kind::Laser) x[c0] = a.offset[f];
  if (kind == ProbeFeature::Kind::Ballbar) {
    const int k = ballbar_plane(plan_.features[f]);
    x[c0] = a.ball[f][(k + 1) % 3];
    x[c0 + 1] = a.ball[f][(k + 2) % 3];
    x[c0 + 2] = a.offset[f];
  }
}

Eigen::VectorXd ProbingModel::initial() const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n_));
  for (std::size_t i = 0; i < params_.size(); ++i) x[static_cast<Eigen::Index>(i)] = base_.parameter(params_[i]);
  const ArtefactState a = nominal_artefact(plan_);
  std::vector<bool> used(plan_.features.size(), false);
  for (const auto& r : plan_.records) used[r.feature] = true;
  for (std::size_t f = 0; f < plan_.features.size(); ++f) {
    if (!used[f]) continue;
    put_artefact(f, a, x.data());
  }
  return x;
}

Machine ProbingModel::machine(const double* x) const {
  Machine m = base_;
  for (std::size_t i = 0; i < params_.size(); ++i) m.set_parameter(params_[i], x[i]);
  return m;
}

ArtefactState ProbingModel::artefact(const double* x) const {
  ArtefactState a = nominal_artefact(plan_);
  std::vector<bool> used(plan_.features.size(), false);
  for (const auto& r : plan_.records) used[r.feature] = true;
  for (std::size_t f = 0; f < plan_.features.size(); ++f) {
    if (!used[f]) continue;
    const auto kind = plan_.features[f].kind;
    const std::size_t c0 = col_[f];
    if (kind == ProbeFeature::Kind::Ball) a.ball[f] = Vec3(x[c0], x[c0 + 1], x[c0 + 2]);
    if (kind == ProbeFeature::Kind::Facet || kind == ProbeFeature::Kind::Laser) a.offset[f] = x[c0];
    if (kind == ProbeFeature::Kind::Ballbar) {
      const int k = ballbar_plane(plan_.features[f]);
      a.ball[f][(k + 1) % 3] = x[c0];
      a.ball[f][(k + 2) % 3] = x[c0 + 1];
      a.offset[f] = x[c0 + 2];
    }
  }
  return a;
}

const ErrorModel& ProbingModel::model(const double* x) const {
  if (!model_ || !std::equal(cached_.begin(), cached_.end(), x)) {
    cached_.assign(x, x + params_.size());
    model_ = std::make_unique<ErrorModel>(machine(x));
    full_.resize(6, static_cast<Eigen::Index>(base_.parameter_count()));
  }
  return *model_;
}

void ProbingModel::block(const double* x, std::size_t b, double* r, double* J) const {
  const std::size_t rows = block_size(b);
  if (J) std::fill(J, J + rows * n_, 0.0);
  if (b >= plan_.records.size()) {
    const Bar& bar = bars_[b - plan_.records.size()];
    const Vec3 ca(x[col_[bar.a]], x[col_[bar.a] + 1], x[col_[bar.a] + 2]);
    const Vec3 cb(x[col_[bar.b]], x[col_[bar.b] + 1], x[col_[bar.b] + 2]);
    const Vec3 d = ca - cb;
    const double len = d.norm();
    r[0] = (len - bar.length) / ss_;
    if (J && len > 0)
      for (int c = 0; c < 3; ++c) {
        J[col_[bar.a] + static_cast<std::size_t>(c)] = d[c] / len / ss_;
        J[col_[bar.b] + static_cast<std::size_t>(c)] = -d[c] / len / ss_;
      }
    return;
  }
  const ProbingRecord& rec = plan_.records[b];
  const ProbeFeature& f = plan_.features[rec.feature];
  const ErrorModel& em = model(x);
  const Vec3 p = em.actual_pose(rec.q, rec.dir).t;
  if (J && !params_.empty()) em.jacobian(rec.q, rec.dir, full_, ws_);
  if (f.kind == ProbeFeature::Kind::Ball) {
    const Vec3 c(x[col_[rec.feature]], x[col_[rec.feature] + 1], x[col_[rec.feature] + 2]);
    for (int k = 0; k < 3; ++k) r[k] = (p[k] - c[k]) / sb_;
    if (!J) return;
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t i = 0; i < params_.size(); ++i)
        J[k * n_ + i] = full_(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(params_[i])) / sb_;
      J[k * n_ + col_[rec.feature] + k] = -1.0 / sb_;
    }
    return;
  }
  if (f.kind == ProbeFeature::Kind::Ballbar) {
    // The bar's length: |p - c| (ISO 230-4), read delta long; c the pivot, its in-plane
    // coordinates unknowns. First order in the errors through p.
    const std::size_t c0 = col_[rec.feature];
    const int k = ballbar_plane(f);
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    Vec3 c = f.position;
    c[k1] = x[c0];
    c[k2] = x[c0 + 1];
    const Vec3 d = p - c;
    const double len = d.norm();
    r[0] = (len + x[c0 + 2] - rec.reading) / sbb_;
    if (!J || !(len > 0)) return;
    const Vec3 u = d / len;
    for (std::size_t i = 0; i < params_.size(); ++i)
      J[i] = u.dot(full_.col(static_cast<Eigen::Index>(params_[i])).head<3>()) / sbb_;
    J[c0] = -u[k1] / sbb_;
    J[c0 + 1] = -u[k2] / sbb_;
    J[c0 + 2] = 1.0 / sbb_;
    return;
  }
  if (f.kind == ProbeFeature::Kind::Laser) {
    // The displacement along the beam (ISO 230-2): d . p less the offset where the laser was zeroed.
    r[0] = (f.normal.dot(p) - x[col_[rec.feature]] - rec.reading) / sl_;
    if (!J) return;
    for (std::size_t i = 0; i < params_.size(); ++i)
      J[i] = f.normal.dot(full_.col(static_cast<Eigen::Index>(params_[i])).head<3>()) / sl_;
    J[col_[rec.feature]] = -1.0 / sl_;
    return;
  }
  const double pre = pretravel_ ? x[pre_col_] : 0.0;
  r[0] = (f.normal.dot(p) - x[col_[rec.feature]] + pre) / sf_;
  if (!J) return;
  for (std::size_t i = 0; i < params_.size(); ++i)
    J[i] = f.normal.dot(full_.col(static_cast<Eigen::Index>(params_[i])).head<3>()) / sf_;
  J[col_[rec.feature]] = -1.0 / sf_;
  if (pretravel_) J[pre_col_] = 1.0 / sf_;
}

void ProbingModel::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd* J) const {
  r.resize(static_cast<Eigen::Index>(m_));
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows;
  if (J) J->resize(static_cast<Eigen::Index>(m_), static_cast<Eigen::Index>(n_));
  std::size_t row = 0;
  for (std::size_t b = 0; b < blocks(); ++b) {
    const std::size_t s = block_size(b);
    rows.resize(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(n_));
    block(x.data(), b, r.data() + row, J ? rows.data() : nullptr);
    if (J) J->middleRows(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(s)) = rows;
    row += s;
  }
}

}  // namespace mtcal::detail
