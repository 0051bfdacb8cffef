// The sparse equations of motion of an RLC circuit (dcad/fast/rlc_sparse.hpp).
#include "dcad/fast/rlc_sparse.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>

namespace dcad::fast::sparse_rlc {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;
using rlc::Kind;

bool joins(Kind k) { return k == Kind::voltage || k == Kind::wire; }

SpMat build(Eigen::Index rows, Eigen::Index cols, const Triplets& t) {
  SpMat m(rows, cols);
  m.setFromTriplets(t.begin(), t.end());
  m.makeCompressed();
  return m;
}

}  // namespace

std::string Model::name(long node) const {
  if (node < 0) return "0";
  return static_cast<std::size_t>(node) < c_.node_names.size() ? c_.node_names[static_cast<std::size_t>(node)]
                                                               : "n" + std::to_string(node);
}

Model::Model(const Network& c) : c_(c) {
  const std::size_t n = c.branches.size(), nv = c.nodes + 1, ms = c.sources;
  for (std::size_t b = 0; b < n; ++b) {
    const Element& br = c.branches[b];
    if ((br.kind == Kind::capacitor || br.kind == Kind::resistor || br.kind == Kind::inductor) &&
        !(br.value > 0 && std::isfinite(br.value)))
      throw std::invalid_argument("branch " + std::to_string(b) + ": expected a positive finite value");
    if ((br.kind == Kind::voltage || br.kind == Kind::current) &&
        (br.source < 0 || static_cast<std::size_t>(br.source) >= ms))
      throw std::invalid_argument("branch " + std::to_string(b) + ": source index out of range");
  }
  // 1.–3. the contractions (dcad/rlc_state.hpp)
  std::vector<rlc::Branch> topo(n);
  std::vector<long> src(n, -1);
  for (std::size_t b = 0; b < n; ++b) {
    topo[b] = {c.branches[b].kind, c.branches[b].from, c.branches[b].to};
    src[b] = c.branches[b].source;
  }
  const rlc::StateStructure st = rlc::state_structure(c.nodes, topo, src);
  nsup_ = st.supernodes;
  nw_ = st.nw;
  nr_ = st.nr;
  ne_ = st.ne;
  sup_ = st.supernode;
  croot_ = st.croot;
  for (const rlc::StateStructure::TreeEdge& e : st.vtree) vtree_.push_back({e.node, e.parent, e.branch});
  const auto sup_v = [&](long node) { return st.super(node); };  // −1 ground
  {
    Triplets t;
    for (std::size_t b = 0; b < n; ++b) {
      for (const auto& [j, s] : st.offset[static_cast<std::size_t>(c.branches[b].from + 1)]) t.emplace_back(b, j, s);
      for (const auto& [j, s] : st.offset[static_cast<std::size_t>(c.branches[b].to + 1)]) t.emplace_back(b, j, -s);
    }
    ob_ = build(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(ms), t);
    Triplets tn;
    for (std::size_t v = 0; v < c.nodes; ++v)
      for (const auto& [j, s] : st.offset[v + 1]) tn.emplace_back(v, j, s);
    on_ = build(static_cast<Eigen::Index>(c.nodes), static_cast<Eigen::Index>(ms), tn);
  }
  // per-kind incidences on supernodes (self-loops drop out), branch lists
  lof_.assign(n, -1);
  Triplets tc, tr, tl, ti;
  for (std::size_t b = 0; b < n; ++b) {
    const Element& br = c.branches[b];
    const long a = sup_v(br.from), z = sup_v(br.to);
    const auto add = [&](Triplets& t, std::size_t col) {
      if (a == z) return;
      if (a >= 0) t.emplace_back(a, col, 1.0);
      if (z >= 0) t.emplace_back(z, col, -1.0);
    };
    switch (br.kind) {
      case Kind::capacitor:
        add(tc, cidx_.size());
        cidx_.push_back(b);
        break;
      case Kind::resistor:
        add(tr, ridx_.size());
        ridx_.push_back(b);
        break;
      case Kind::inductor:
        add(tl, lidx_.size());
        lof_[b] = static_cast<long>(lidx_.size());
        lidx_.push_back(b);
        break;
      case Kind::current:
        add(ti, iidx_.size());
        iidx_.push_back(b);
        break;
      default: break;
    }
    if (br.kind != Kind::capacitor) qx_.push_back(b);
  }
  nl_ = lidx_.size();
  const auto ns = static_cast<Eigen::Index>(nsup_);
  AC_ = build(ns, static_cast<Eigen::Index>(cidx_.size()), tc);
  AR_ = build(ns, static_cast<Eigen::Index>(ridx_.size()), tr);
  AL_ = build(ns, static_cast<Eigen::Index>(nl_), tl);
  AI_ = build(ns, static_cast<Eigen::Index>(iidx_.size()), ti);
  cdiag_.resize(static_cast<Eigen::Index>(cidx_.size()));
  for (std::size_t k = 0; k < cidx_.size(); ++k) cdiag_(static_cast<Eigen::Index>(k)) = c.branches[cidx_[k]].value;
  rdiag_g_.resize(static_cast<Eigen::Index>(ridx_.size()));
  for (std::size_t k = 0; k < ridx_.size(); ++k)
    rdiag_g_(static_cast<Eigen::Index>(k)) = 1.0 / c.branches[ridx_[k]].value;

  wv_.assign(nsup_, -1);
  {
    Triplets t;
    for (std::size_t s = 0; s < nsup_; ++s) {
      const rlc::StateStructure::Levels& l = st.levels[s];
      wv_[s] = l.w;
      if (l.w >= 0) t.emplace_back(s, l.w, 1.0);
      if (l.r >= 0) t.emplace_back(s, static_cast<long>(nw_) + l.r, 1.0);
      if (l.e >= 0) t.emplace_back(s, static_cast<long>(nw_ + nr_) + l.e, 1.0);
    }
    m_.T = build(ns, static_cast<Eigen::Index>(nw_ + nr_ + ne_), t);
  }
  const SpMat Tw = m_.T.leftCols(static_cast<Eigen::Index>(nw_)),
              Tr = m_.T.middleCols(static_cast<Eigen::Index>(nw_), static_cast<Eigen::Index>(nr_)),
              Te = m_.T.rightCols(static_cast<Eigen::Index>(ne_));
  const SpMat Cn = AC_ * cdiag_.asDiagonal() * SpMat(AC_.transpose()),
              Gn = AR_ * rdiag_g_.asDiagonal() * SpMat(AR_.transpose());
  m_.Cww = SpMat(Tw.transpose()) * Cn * Tw;
  m_.Gww = SpMat(Tw.transpose()) * Gn * Tw;
  m_.Gwr = SpMat(Tw.transpose()) * Gn * Tr;
  m_.Grr = SpMat(Tr.transpose()) * Gn * Tr;
  m_.Lw = SpMat(Tw.transpose()) * AL_;
  m_.Lr = SpMat(Tr.transpose()) * AL_;
  m_.Le = SpMat(Te.transpose()) * AL_;
  // source maps
  const auto rows_of = [&](const std::vector<std::size_t>& idx) {
    Triplets t;
    for (std::size_t k = 0; k < idx.size(); ++k) t.emplace_back(k, idx[k], 1.0);
    return SpMat(build(static_cast<Eigen::Index>(idx.size()), static_cast<Eigen::Index>(n), t) * ob_);
  };
  Triplets tsel;
  for (std::size_t k = 0; k < iidx_.size(); ++k) tsel.emplace_back(k, c.branches[iidx_[k]].source, 1.0);
  const SpMat Isel = build(static_cast<Eigen::Index>(iidx_.size()), static_cast<Eigen::Index>(ms), tsel);
  const SpMat inj = AR_ * rdiag_g_.asDiagonal() * rows_of(ridx_) + AI_ * Isel;
  m_.Hw = SpMat(Tw.transpose()) * inj;
  m_.Hwd = SpMat(Tw.transpose()) * AC_ * cdiag_.asDiagonal() * rows_of(cidx_);
  m_.Hr = SpMat(Tr.transpose()) * inj;
  m_.Ie = SpMat(Te.transpose()) * AI_ * Isel;
  m_.Ol = rows_of(lidx_);
  Crow_ = cdiag_.asDiagonal() * SpMat(AC_.transpose()) * Tw;
  // Φ and its inverse, block by block over the groups of coupled inductors
  {
    Triplets t;
    for (std::size_t k = 0; k < nl_; ++k) t.emplace_back(k, k, c.branches[lidx_[k]].value);
    std::vector<std::pair<std::size_t, std::size_t>> mends;
    std::vector<bool> all;
    for (const Coupling& mu : c.mutuals) {
      if (lof_.at(mu.a) < 0 || lof_.at(mu.b) < 0)
        throw std::invalid_argument("a coupling between branches that are not inductors");
      t.emplace_back(lof_[mu.a], lof_[mu.b], mu.m);
      t.emplace_back(lof_[mu.b], lof_[mu.a], mu.m);
      mends.emplace_back(static_cast<std::size_t>(lof_[mu.a]), static_cast<std::size_t>(lof_[mu.b]));
      all.push_back(true);
    }
    m_.phi = build(static_cast<Eigen::Index>(nl_), static_cast<Eigen::Index>(nl_), t);
    const rlc::Forest fg = rlc::forest(nl_, mends, all);
    std::vector<std::vector<std::size_t>> groups(nl_);
    for (std::size_t k = 0; k < nl_; ++k) groups[fg.root[k]].push_back(k);
    const Eigen::MatrixXd phid = nl_ <= 64 ? Eigen::MatrixXd(m_.phi) : Eigen::MatrixXd();
    Triplets ti2;
    for (const std::vector<std::size_t>& g : groups) {
      if (g.empty()) continue;
      Eigen::MatrixXd blk(g.size(), g.size());
      for (std::size_t i = 0; i < g.size(); ++i)
        for (std::size_t j = 0; j < g.size(); ++j)
          blk(i, j) = m_.phi.coeff(static_cast<Eigen::Index>(g[i]), static_cast<Eigen::Index>(g[j]));
      Eigen::LLT<Eigen::MatrixXd> llt(blk);
      if (llt.info() != Eigen::Success) throw std::invalid_argument("the inductance matrix is not positive definite");
      const Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(g.size(), g.size()));
      for (std::size_t i = 0; i < g.size(); ++i)
        for (std::size_t j = 0; j < g.size(); ++j) ti2.emplace_back(g[i], g[j], inv(i, j));
    }
    phi_inv_ = build(static_cast<Eigen::Index>(nl_), static_cast<Eigen::Index>(nl_), ti2);
  }
  cww_.compute(m_.Cww);
  grr_.compute(m_.Grr);
  const SpMat schur = m_.Le * phi_inv_ * SpMat(m_.Le.transpose());
  schur_.compute(schur);
  if ((nw_ && cww_.info() != Eigen::Success) || (nr_ && grr_.info() != Eigen::Success) ||
      (ne_ && schur_.info() != Eigen::Success))
    throw std::invalid_argument("a reduced matrix is not positive definite (a value out of double's range?)");
}

void Model::rate(const double* x, const double* sigma, const double* dsigma, double* xdot, double* current,
                 Vec* potentials) const {
  const auto ms = static_cast<Eigen::Index>(c_.sources);
  const Eigen::Map<const Vec> w(x, static_cast<Eigen::Index>(nw_)), i(x + nw_, static_cast<Eigen::Index>(nl_)),
      s(sigma, ms), ds(dsigma, ms);
  Vec rho(static_cast<Eigen::Index>(nr_)), e(static_cast<Eigen::Index>(ne_));
  if (nr_) rho = -grr_.solve(m_.Gwr.transpose() * w + m_.Lr * i + m_.Hr * s);
  Vec ul = m_.Lw.transpose() * w + m_.Ol * s;
  if (nr_) ul += m_.Lr.transpose() * rho;
  if (ne_) {
    e = -schur_.solve(m_.Ie * ds + m_.Le * (phi_inv_ * ul));
    ul += m_.Le.transpose() * e;
  }
  Eigen::Map<Vec> wdot(xdot, static_cast<Eigen::Index>(nw_)), idot(xdot + nw_, static_cast<Eigen::Index>(nl_));
  if (nl_) idot = phi_inv_ * ul;
  if (nw_) {
    Vec rhs = m_.Gww * w + m_.Lw * i + m_.Hw * s + m_.Hwd * ds;
    if (nr_) rhs += m_.Gwr * rho;
    wdot = -cww_.solve(rhs);
  }
  if (!current && !potentials) return;
  const std::size_t n = c_.branches.size();
  Vec E = m_.T.leftCols(static_cast<Eigen::Index>(nw_)) * w;
  if (nr_) E += m_.T.middleCols(static_cast<Eigen::Index>(nw_), static_cast<Eigen::Index>(nr_)) * rho;
  if (ne_) E += m_.T.rightCols(static_cast<Eigen::Index>(ne_)) * e;
  if (potentials) *potentials = E;
  if (!current) return;
  const Vec ob = ob_ * s, obd = ob_ * ds;
  const Vec ur = AR_.transpose() * E;
  const Vec ic = nw_ ? Vec(Crow_ * wdot) : Vec::Zero(static_cast<Eigen::Index>(cidx_.size()));
  std::vector<double> ib(n, 0.0);
  for (std::size_t k = 0; k < ridx_.size(); ++k)
    ib[ridx_[k]] = (ur(static_cast<Eigen::Index>(k)) + ob(static_cast<Eigen::Index>(ridx_[k]))) *
                   rdiag_g_(static_cast<Eigen::Index>(k));
  for (std::size_t k = 0; k < cidx_.size(); ++k)
    ib[cidx_[k]] = ic(static_cast<Eigen::Index>(k)) +
                   cdiag_(static_cast<Eigen::Index>(k)) * obd(static_cast<Eigen::Index>(cidx_[k]));
  for (std::size_t k = 0; k < nl_; ++k) ib[lidx_[k]] = i(static_cast<Eigen::Index>(k));
  for (std::size_t k = 0; k < iidx_.size(); ++k) ib[iidx_[k]] = s(c_.branches[iidx_[k]].source);
  source_currents(ib);
  for (std::size_t k = 0; k < qx_.size(); ++k) current[k] = ib[qx_[k]];
}

BranchValues Model::values(const double* x, const double* qx, const double* sigma, const double* dsigma) const {
  const std::size_t n = c_.branches.size();
  const auto nn = static_cast<Eigen::Index>(n);
  BranchValues v{Vec::Zero(nn), Vec::Zero(nn), Vec::Zero(nn), Vec::Zero(nn)};
  std::vector<double> xdot(nw_ + nl_), cur(qx_.size());
  Vec E;
  rate(x, sigma, dsigma, xdot.data(), cur.data(), &E);
  for (std::size_t k = 0; k < qx_.size(); ++k) {
    v.q(static_cast<Eigen::Index>(qx_[k])) = qx[k];
    v.i(static_cast<Eigen::Index>(qx_[k])) = cur[k];
  }
  const auto ms = static_cast<Eigen::Index>(c_.sources);
  const Eigen::Map<const Vec> s(sigma, ms), ds(dsigma, ms);
  const Vec ob = ob_ * s, obd = ob_ * ds;
  for (std::size_t b = 0; b < n; ++b) {
    const long a = c_.branches[b].from < 0 ? -1 : sup_[static_cast<std::size_t>(c_.branches[b].from)];
    const long z = c_.branches[b].to < 0 ? -1 : sup_[static_cast<std::size_t>(c_.branches[b].to)];
    v.u(static_cast<Eigen::Index>(b)) =
        (a >= 0 ? E(a) : 0.0) - (z >= 0 ? E(z) : 0.0) + ob(static_cast<Eigen::Index>(b));
  }
  const Vec ic = nw_ ? Vec(Crow_ * Eigen::Map<const Vec>(xdot.data(), static_cast<Eigen::Index>(nw_)))
                     : Vec::Zero(static_cast<Eigen::Index>(cidx_.size()));
  for (std::size_t k = 0; k < cidx_.size(); ++k) {
    const auto b = static_cast<Eigen::Index>(cidx_[k]), kk = static_cast<Eigen::Index>(k);
    v.q(b) = cdiag_(kk) * v.u(b);
    v.i(b) = ic(kk) + cdiag_(kk) * obd(b);
  }
  const Eigen::Map<const Vec> il(x + nw_, static_cast<Eigen::Index>(nl_));
  const Vec p = m_.phi * il;
  for (std::size_t k = 0; k < nl_; ++k) v.p(static_cast<Eigen::Index>(lidx_[k])) = p(static_cast<Eigen::Index>(k));
  return v;
}

void Model::source_currents(std::vector<double>& ib) const {
  std::vector<double> net(c_.nodes + 1, 0.0);
  for (std::size_t b = 0; b < ib.size(); ++b) {
    if (joins(c_.branches[b].kind)) continue;
    net[static_cast<std::size_t>(c_.branches[b].from + 1)] += ib[b];
    net[static_cast<std::size_t>(c_.branches[b].to + 1)] -= ib[b];
  }
  for (auto it = vtree_.rbegin(); it != vtree_.rend();
       ++it) {  // leaves first: KCL at the child gives its source's current
    const Element& br = c_.branches[it->branch];
    const std::size_t ch = static_cast<std::size_t>(it->node + 1), pa = static_cast<std::size_t>(it->parent + 1);
    const double cur = br.from == it->node ? -net[ch] : net[ch];
    ib[it->branch] = cur;
    net[pa] += br.from == it->parent ? cur : -cur;
  }
}

Vec Model::impulse_charges(const Vec& q_before, const Vec& q_after) const {
  std::vector<double> dq(c_.branches.size(), 0.0);
  for (std::size_t b : cidx_) dq[b] = q_after(static_cast<Eigen::Index>(b)) - q_before(static_cast<Eigen::Index>(b));
  source_currents(dq);
  Vec out(static_cast<Eigen::Index>(qx_.size()));
  for (std::size_t k = 0; k < qx_.size(); ++k) out(static_cast<Eigen::Index>(k)) = dq[qx_[k]];
  return out;
}

Vec Model::node_potentials(const double* x, const double* sigma, const double* dsigma) const {
  std::vector<double> xdot(nw_ + nl_);
  Vec E;
  rate(x, sigma, dsigma, xdot.data(), nullptr, &E);
  Vec e = on_ * Eigen::Map<const Vec>(sigma, static_cast<Eigen::Index>(c_.sources));
  for (std::size_t v = 0; v < c_.nodes; ++v)
    if (sup_[v] >= 0) e(static_cast<Eigen::Index>(v)) += E(sup_[v]);
  return e;
}

Vec Model::energy_scale() const {
  Vec d(static_cast<Eigen::Index>(nw_ + nl_));
  for (std::size_t k = 0; k < nw_; ++k)
    d(static_cast<Eigen::Index>(k)) =
        std::sqrt(m_.Cww.coeff(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
  for (std::size_t k = 0; k < nl_; ++k)
    d(static_cast<Eigen::Index>(nw_ + k)) =
        std::sqrt(m_.phi.coeff(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
  return d;
}

Vec Model::from_charges(const Vec& q_before, const Vec& i_before, const double* sigma) const {
  const Eigen::Map<const Vec> s(sigma, static_cast<Eigen::Index>(c_.sources));
  Vec x(static_cast<Eigen::Index>(nw_ + nl_));
  if (nw_) {
    Vec qc(static_cast<Eigen::Index>(cidx_.size()));
    const Vec ob = ob_ * s;
    for (std::size_t k = 0; k < cidx_.size(); ++k)
      qc(static_cast<Eigen::Index>(k)) = q_before(static_cast<Eigen::Index>(cidx_[k])) -
                                         cdiag_(static_cast<Eigen::Index>(k)) * ob(static_cast<Eigen::Index>(cidx_[k]));
    x.head(static_cast<Eigen::Index>(nw_)) =
        cww_.solve(Vec(SpMat(m_.T.leftCols(static_cast<Eigen::Index>(nw_)).transpose()) * (AC_ * qc)));
  }
  Vec il(static_cast<Eigen::Index>(nl_));
  for (std::size_t k = 0; k < nl_; ++k)
    il(static_cast<Eigen::Index>(k)) = i_before(static_cast<Eigen::Index>(lidx_[k]));
  if (ne_) il -= phi_inv_ * (SpMat(m_.Le.transpose()) * schur_.solve(Vec(m_.Le * il + m_.Ie * s)));
  x.tail(static_cast<Eigen::Index>(nl_)) = il;
  return x;
}

Model::DcHolds Model::dc_holds(const std::vector<std::pair<long, double>>& held, const rlc::Forest& fl,
                               const std::vector<double>& t, const Vec& on) const {
  const std::size_t nv = nsup_ + 1;
  DcHolds h{std::vector<double>(nv, 0.0), std::vector<bool>(nv, false), std::vector<long>(nv, -1)};
  std::vector<double>& fixed = h.fixed;
  std::vector<bool>& is_fixed = h.is_fixed;
  std::vector<long>& hold_at = h.hold_at;
  for (const auto& [node, value] : held) {
    const std::size_t v = vertex(node), r = fl.root[v];
    const double p = value - t[v] - on(node);
    const bool ground = r == fl.root[0];
    const double known = ground ? 0.0 : fixed[r];
    if ((ground || is_fixed[r]) && std::abs(known - p) > 1e-12 * std::max({1.0, std::abs(p), std::abs(known)}))
      throw std::domain_error(
          ".ic v(" + name(node) + ") = " + std::to_string(value) +
          " contradicts ground or another .ic through voltage sources, wires and inductors (shorts at DC)");
    if (ground) continue;  // already what ground's sources make it
    is_fixed[r] = true;
    fixed[r] = p;
    if (hold_at[r] < 0) hold_at[r] = static_cast<long>(v);
  }
  return h;
}

void Model::dc_resistors(const rlc::Forest& fl, const std::vector<long>& dc, const std::vector<double>& t,
                         const DcHolds& holds, const Vec& obs, std::vector<Eigen::Triplet<double>>& tg, Vec& rhs,
                         std::vector<std::pair<std::size_t, std::size_t>>& rends, std::vector<bool>& rall) const {
  const auto level = [&](std::size_t root) {  // a known root level (0: ground's)
    return holds.is_fixed[root] ? holds.fixed[root] : 0.0;
  };
  for (std::size_t k = 0; k < ridx_.size(); ++k) {
    const Element& br = c_.branches[ridx_[k]];
    const std::size_t a = vertex(br.from), z = vertex(br.to);
    rends.emplace_back(fl.root[a], fl.root[z]);
    rall.push_back(true);
    const double g = rdiag_g_(static_cast<Eigen::Index>(k));
    const long da = dc[fl.root[a]], dz = dc[fl.root[z]];
    // known levels (held or ground) move to the right-hand side with the offsets
    const double o = obs(static_cast<Eigen::Index>(ridx_[k])) + t[a] - t[z] + (da < 0 ? level(fl.root[a]) : 0.0) -
                     (dz < 0 ? level(fl.root[z]) : 0.0);
    // i = g (P_a − P_z + o)
    if (da >= 0) {
      tg.emplace_back(da, da, g);
      if (dz >= 0) tg.emplace_back(da, dz, -g);
      rhs(da) -= g * o;
    }
    if (dz >= 0) {
      tg.emplace_back(dz, dz, g);
      if (da >= 0) tg.emplace_back(dz, da, -g);
      rhs(dz) += g * o;
    }
  }
}

std::size_t Model::vertex(long node) const {
  return static_cast<std::size_t>((node < 0 ? -1 : sup_[static_cast<std::size_t>(node)]) + 1);
}

Vec Model::dc_inductor_currents(const Vec& E, const double* sigma, const Vec& obs, const rlc::Forest& fl,
                                const std::vector<std::pair<std::size_t, std::size_t>>& ends,
                                const std::vector<bool>& is_fixed, const std::vector<long>& hold_at) const {
  const std::size_t nv = nsup_ + 1;
  std::vector<double> net(nv, 0.0);  // supernode outflow of resistors and current sources
  for (std::size_t k = 0; k < ridx_.size(); ++k) {
    const Element& br = c_.branches[ridx_[k]];
    const std::size_t a = vertex(br.from), z = vertex(br.to);
    const double ea = a ? E(static_cast<Eigen::Index>(a - 1)) : 0.0, ez = z ? E(static_cast<Eigen::Index>(z - 1)) : 0.0;
    const double cur = rdiag_g_(static_cast<Eigen::Index>(k)) * (ea - ez + obs(static_cast<Eigen::Index>(ridx_[k])));
    net[a] += cur;
    net[z] -= cur;
  }
  for (std::size_t k = 0; k < iidx_.size(); ++k) {
    const Element& br = c_.branches[iidx_[k]];
    net[vertex(br.from)] += sigma[br.source];
    net[vertex(br.to)] -= sigma[br.source];
  }
  // a hold source delivers what its DC node's KCL lacks, at its own node
  std::vector<double> total(nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v) total[fl.root[v]] += net[v];
  for (std::size_t r = 0; r < nv; ++r)
    if (is_fixed[r]) net[static_cast<std::size_t>(hold_at[r])] -= total[r];
  Vec il = Vec::Zero(static_cast<Eigen::Index>(nl_));
  for (auto it = fl.tree.rbegin(); it != fl.tree.rend(); ++it) {
    const double cur = ends[it->edge].first == it->child ? -net[it->child] : net[it->child];
    il(static_cast<Eigen::Index>(it->edge)) = cur;
    net[it->parent] += ends[it->edge].first == it->parent ? cur : -cur;
  }
  return il;
}

Vec Model::operating_point(const double* sigma, const std::vector<std::pair<long, double>>& held) const {
  // inductors are shorts: they join supernodes into DC nodes, with offsets E_from − E_to = −o_L σ
  const Eigen::Map<const Vec> s(sigma, static_cast<Eigen::Index>(c_.sources));
  const std::size_t nv = nsup_ + 1;
  std::vector<std::pair<std::size_t, std::size_t>> ends(nl_);
  std::vector<bool> all(nl_, true);
  std::vector<long> rep(nv, -1);  // a node of each supernode, for messages
  for (std::size_t k = 0; k < c_.nodes; ++k)
    if (rep[static_cast<std::size_t>(sup_[k] + 1)] < 0)
      rep[static_cast<std::size_t>(sup_[k] + 1)] = static_cast<long>(k);
  const auto sv = [&](long node) { return vertex(node); };
  for (std::size_t k = 0; k < nl_; ++k) ends[k] = {sv(c_.branches[lidx_[k]].from), sv(c_.branches[lidx_[k]].to)};
  const rlc::Forest fl = rlc::forest(nv, ends, all);
  const Vec ol = m_.Ol * s, obs = ob_ * s;
  for (std::size_t k = 0; k < nl_; ++k)
    if (!fl.in_tree[k])
      throw std::domain_error("the DC operating point is not unique: " + c_.branch_names.at(lidx_[k]) +
                              " closes a loop of inductors, voltage sources and wires, whose current DC leaves free "
                              "(ngspice: singular matrix)");
  std::vector<double> t(nv, 0.0);
  for (const rlc::Forest::Edge& e : fl.tree) {  // E_child = E_parent ± (−o_L σ)
    const double d = -ol(static_cast<Eigen::Index>(e.edge));
    t[e.child] = t[e.parent] + (e.child == ends[e.edge].first ? d : -d);
  }
  // `.ic` holds: a held node fixes its DC node's potential (root level P with e_node = P + t + o_node σ)
  const DcHolds holds = dc_holds(held, fl, t, on_ * s);
  const std::vector<double>& fixed = holds.fixed;
  const std::vector<bool>& is_fixed = holds.is_fixed;
  const std::vector<long>& hold_at = holds.hold_at;
  std::vector<long> dc(nv, -1);
  std::size_t ndc = 0;
  for (std::size_t v = 0; v < nv; ++v)
    if (fl.root[v] != fl.root[0] && !is_fixed[fl.root[v]] && dc[fl.root[v]] < 0)
      dc[fl.root[v]] = static_cast<long>(ndc++);
  const auto level = [&](std::size_t root) {
    return is_fixed[root] ? fixed[root] : 0.0;
  };  // a known root level (0: ground's)
  std::vector<std::pair<std::size_t, std::size_t>> rends;
  std::vector<bool> rall;
  Triplets tg;
  Vec rhs = Vec::Zero(static_cast<Eigen::Index>(ndc));
  dc_resistors(fl, dc, t, holds, obs, tg, rhs, rends, rall);  // a Laplacian grounded at ground's DC node
  for (std::size_t k = 0; k < iidx_.size(); ++k) {
    const Element& br = c_.branches[iidx_[k]];
    const double cur = s(br.source);
    const long da = dc[fl.root[sv(br.from)]], dz = dc[fl.root[sv(br.to)]];
    if (da >= 0) rhs(da) -= cur;
    if (dz >= 0) rhs(dz) += cur;
  }
  for (std::size_t v = 0; v < nv; ++v)  // a held DC node reaches ground through its hold source
    if (is_fixed[v]) {
      rends.emplace_back(v, fl.root[0]);
      rall.push_back(true);
    }
  const rlc::Forest fr = rlc::forest(nv, rends, rall);
  for (std::size_t v = 1; v < nv; ++v)
    if (fr.root[fl.root[v]] != fr.root[fl.root[0]])
      throw std::domain_error(
          "the DC operating point is not unique: node " + name(rep[v]) +
          " has no path of resistors, inductors, voltage sources or wires to ground (ngspice: singular matrix)");
  Vec pot = Vec::Zero(static_cast<Eigen::Index>(ndc));
  if (ndc) {
    Eigen::SimplicialLLT<SpMat> llt(build(static_cast<Eigen::Index>(ndc), static_cast<Eigen::Index>(ndc), tg));
    if (llt.info() != Eigen::Success)
      throw std::domain_error("the DC conductance matrix is not positive definite in double");
    pot = llt.solve(rhs);
  }
  Vec E(static_cast<Eigen::Index>(nsup_));
  for (std::size_t v = 1; v < nv; ++v)
    E(static_cast<Eigen::Index>(v - 1)) = (dc[fl.root[v]] >= 0 ? pot(dc[fl.root[v]]) : level(fl.root[v])) + t[v];
  const Vec il = dc_inductor_currents(E, sigma, obs, fl, ends, is_fixed, hold_at);
  // the state: w = E − (the potential of its C-component's root; 0 for the component of ground)
  Vec x(static_cast<Eigen::Index>(nw_ + nl_));
  for (std::size_t k = 0; k < nsup_; ++k)
    if (wv_[k] >= 0) x(wv_[k]) = E(static_cast<Eigen::Index>(k)) - (croot_[k] >= 0 ? E(croot_[k]) : 0.0);
  x.tail(static_cast<Eigen::Index>(nl_)) = il;
  return x;
}

}  // namespace dcad::fast::sparse_rlc
