// The linear DAE form at circuit size, certified (dae_sparse.hpp: the tower and why every rank is proved).
#include "dcad/certified/dae_sparse.hpp"

#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/reference/pipeline/dae.hpp"

#include <flint/fmpq.h>
#include <flint/fmpz.h>
#include <flint/ulong_extras.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <queue>
#include <set>
#include <sstream>
#include <unordered_map>

namespace dcad::certified {

namespace {

using reference::Rational;
using u64 = std::uint64_t;
namespace ex = reference::expr;

/// A sparse exact row: (column, value), columns ascending, no zero stored.
using QRow = std::vector<std::pair<long, Rational>>;

/// Arithmetic modulo a prime p < 2^62.
struct Zp {
  u64 p;
  u64 sub(u64 a, u64 b) const { return a >= b ? a - b : a + (p - b); }
  u64 mul(u64 a, u64 b) const { return static_cast<u64>(static_cast<unsigned __int128>(a) * b % p); }
  u64 inv(u64 a) const { return n_invmod(a, p); }
  /// q mod p; false where p divides q's denominator (q has no value mod p).
  bool of(const Rational& q, u64& out) const {
    const u64 d = mpz_fdiv_ui(boost::multiprecision::denominator(q).backend().data(), p);
    if (d == 0) return false;
    out = mul(mpz_fdiv_ui(boost::multiprecision::numerator(q).backend().data(), p), inv(d));
    return true;
  }
};

/// The elimination's work, bounded: beyond it the route says so rather than run for hours.
constexpr double kWork = 4e8;

/// One prime's elimination of rows (in order): which rows are dependent on the rows before them, and
/// each one's combination (row, coefficient mod p) with its own coefficient 1.
struct ModElimination {
  bool ok = true;  ///< false: p divides a denominator of the data
  std::size_t rank = 0;
  std::vector<std::size_t> dependent;
  std::vector<std::vector<std::pair<std::size_t, u64>>> combination;
};

/// A pivot row of the modular elimination: its column, the inverse of its entry there, the row and its
/// combination of the input rows.
struct ModPivot {
  long col;
  u64 inv;
  std::vector<std::pair<long, u64>> row;
  std::vector<std::pair<std::size_t, u64>> comb;
};

/// The elimination's dense accumulators for the row being reduced (entries by column) and its combination
/// (coefficients by input row), with the positions touched so far: cleared by harvest() for the next row.
struct ModScratch {
  std::vector<u64> acc, cacc;
  std::vector<char> mark, cmark;
  std::vector<long> touched;
  std::vector<std::size_t> ctouched;
  ModScratch(std::size_t cols, std::size_t rows) : acc(cols, 0), cacc(rows, 0), mark(cols, 0), cmark(rows, 0) {}
};

using SlotHeap = std::priority_queue<long, std::vector<long>, std::greater<long>>;  // first taken first

/// The row in `sc` reduced by the pivot slots in `heap` (and those the reduction brings in), in the order
/// they were taken; its combination follows.  Throws beyond the work budget.
void reduce_by_pivots(SlotHeap& heap, const std::vector<ModPivot>& piv, const std::vector<long>& slot_of, const Zp& z,
                      ModScratch& sc, double& work) {
  while (!heap.empty()) {
    const long s = heap.top();
    heap.pop();
    const ModPivot& pv = piv[static_cast<std::size_t>(s)];
    const u64 f = z.mul(sc.acc[static_cast<std::size_t>(pv.col)], pv.inv);
    if (f == 0) continue;  // already reduced (a slot pushed twice)
    for (const auto& [c, v] : pv.row) {
      const std::size_t cc = static_cast<std::size_t>(c);
      if (!sc.mark[cc]) sc.mark[cc] = 1, sc.touched.push_back(c);
      sc.acc[cc] = z.sub(sc.acc[cc], z.mul(f, v));
      if (c != pv.col && sc.acc[cc] && slot_of[cc] >= 0) heap.push(slot_of[cc]);
    }
    sc.acc[static_cast<std::size_t>(pv.col)] = 0;
    for (const auto& [rr, w] : pv.comb) {
      if (!sc.cmark[rr]) sc.cmark[rr] = 1, sc.ctouched.push_back(rr);
      sc.cacc[rr] = z.sub(sc.cacc[rr], z.mul(f, w));
    }
    work += static_cast<double>(pv.row.size() + pv.comb.size());
    if (work > kWork)
      throw reference::NotExactHere("the modular elimination outgrew its budget (" +
                                    std::to_string(static_cast<long>(kWork)) + " operations): fill-in");
  }
}

/// The reduced row's nonzero entries (`left`, by column) and combination (`comb`, by input row), the
/// scratch cleared; returns the column for its pivot (the one fewest rows touch, `weight`), or -1: zero.
long harvest(ModScratch& sc, const std::vector<long>& weight, std::vector<std::pair<long, u64>>& left,
             std::vector<std::pair<std::size_t, u64>>& comb) {
  long best = -1;
  std::sort(sc.touched.begin(), sc.touched.end());
  for (long c : sc.touched) {
    const std::size_t cc = static_cast<std::size_t>(c);
    if (sc.acc[cc]) {
      left.emplace_back(c, sc.acc[cc]);
      if (best < 0 || weight[cc] < weight[static_cast<std::size_t>(best)]) best = c;
    }
    sc.acc[cc] = 0, sc.mark[cc] = 0;
  }
  sc.touched.clear();
  std::sort(sc.ctouched.begin(), sc.ctouched.end());
  for (std::size_t rr : sc.ctouched) {
    if (sc.cacc[rr]) comb.emplace_back(rr, sc.cacc[rr]);
    sc.cacc[rr] = 0, sc.cmark[rr] = 0;
  }
  sc.ctouched.clear();
  return best;
}

/// Rows in order, each reduced by the pivots so far (a pivot row has zeros at the pivot columns taken
/// before it, so reducing by them in the order they were taken never refills one); a row left nonzero
/// takes a pivot (its entry in the column that fewest rows touch, `weight`), one left zero is dependent.
ModElimination eliminate(const std::vector<QRow>& rows, std::size_t cols, const Zp& z, const std::vector<long>& weight,
                         double& work) {
  ModElimination out;
  std::vector<ModPivot> piv;
  std::vector<long> slot_of(cols, -1);
  ModScratch sc(cols, rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    SlotHeap heap;  // pivot slots to reduce by
    for (const auto& [c, q] : rows[r]) {
      u64 v = 0;
      if (!z.of(q, v)) {
        out.ok = false;
        return out;
      }
      sc.acc[static_cast<std::size_t>(c)] = v;
      sc.mark[static_cast<std::size_t>(c)] = 1;
      sc.touched.push_back(c);
      if (v && slot_of[static_cast<std::size_t>(c)] >= 0) heap.push(slot_of[static_cast<std::size_t>(c)]);
    }
    sc.cacc[r] = 1;
    sc.cmark[r] = 1;
    sc.ctouched.push_back(r);
    reduce_by_pivots(heap, piv, slot_of, z, sc, work);
    std::vector<std::pair<long, u64>> left;
    std::vector<std::pair<std::size_t, u64>> comb;
    const long best = harvest(sc, weight, left, comb);
    if (best >= 0) {
      u64 pv = 0;
      for (const auto& [c, v] : left)
        if (c == best) pv = v;
      slot_of[static_cast<std::size_t>(best)] = static_cast<long>(piv.size());
      piv.push_back({best, z.inv(pv), std::move(left), std::move(comb)});
      ++out.rank;
    } else {
      out.dependent.push_back(r);
      out.combination.push_back(std::move(comb));
    }
  }
  return out;
}

/// An exact left null vector: Σ coef_r (row r) = 0, verified in rationals; `own` is its dependent row.
struct NullVector {
  std::size_t own;
  std::vector<std::pair<std::size_t, Rational>> coef;
};

/// FLINT's fmpz, owned.
struct Z {
  fmpz_t v;
  Z() { fmpz_init(v); }
  Z(const Z& o) {
    fmpz_init(v);
    fmpz_set(v, o.v);
  }
  Z& operator=(const Z& o) {
    fmpz_set(v, o.v);
    return *this;
  }
  ~Z() { fmpz_clear(v); }
};

/// Σ coef_r rows[r] is zero, in rationals.
bool verifies(const NullVector& y, const std::vector<QRow>& rows) {
  std::unordered_map<long, Rational> sum;
  for (const auto& [r, q] : y.coef)
    for (const auto& [c, v] : rows[r]) sum[c] += q * v;
  for (const auto& [c, v] : sum)
    if (v != 0) return false;
  return true;
}

constexpr int kPrimes = 96;  ///< at most this many primes (~6,000 bits of modulus) to lift a null space

/// The left null space of `rows` (over `cols` columns), exactly: every vector verified; NotExactHere
/// where no lifting verified within kPrimes primes.  `rank` gets rank_Q(rows) (= rank_p: see the header).
std::vector<NullVector> left_null(const std::vector<QRow>& rows, std::size_t cols, std::size_t& rank,
                                  const std::string& what, long& verified) {
  std::vector<long> weight(cols, 0);  // how many rows touch each column: pivots in the least touched first (less fill)
  for (const QRow& r : rows)
    for (const auto& e : r) ++weight[static_cast<std::size_t>(e.first)];
  double work = 0;
  std::optional<ModElimination> base;
  std::vector<std::map<std::size_t, Z>> residue;  // per dependent row: coefficient mod M
  Z modulus;
  u64 p = (u64{1} << 62) - (u64{1} << 31);
  for (int tried = 0, used = 0; tried < 3 * kPrimes && used < kPrimes; ++tried) {
    p = n_nextprime(p, 1);
    const Zp z{p};
    ModElimination e = eliminate(rows, cols, z, weight, work);
    if (!e.ok) continue;  // p divides a denominator: another prime
    ++used;
    if (!base || e.rank > base->rank) {  // the first prime, or the earlier ones were unlucky (a lower rank)
      base = e;
      fmpz_set_ui(modulus.v, p);
      residue.assign(e.dependent.size(), {});
      for (std::size_t d = 0; d < e.dependent.size(); ++d)
        for (const auto& [r, c] : e.combination[d]) fmpz_set_ui(residue[d][r].v, c);
    } else if (e.rank < base->rank || e.dependent != base->dependent) {
      continue;  // this prime is unlucky
    } else {     // one more residue of every coefficient (CRT); a coefficient 0 mod p is absent from its combination
      for (std::size_t d = 0; d < e.dependent.size(); ++d) {
        std::map<std::size_t, u64> now(e.combination[d].begin(), e.combination[d].end());
        for (const auto& [r, c] : now) residue[d].try_emplace(r);
        for (auto& [r, x] : residue[d]) {
          const auto it = now.find(r);
          fmpz_CRT_ui(x.v, x.v, modulus.v, it == now.end() ? 0 : it->second, p,
                      0);  // in [0, M): reconstruction's range
        }
      }
      fmpz_mul_ui(modulus.v, modulus.v, p);
    }
    // lift (rational reconstruction) and verify exactly — after 1, 2, 4, 8, … primes (each try costs as
    // much as all the eliminations before it)
    if ((used & (used - 1)) && used != kPrimes) continue;
    std::vector<NullVector> out;
    bool lifted = true;
    fmpq_t q;
    fmpq_init(q);
    for (std::size_t d = 0; d < residue.size() && lifted; ++d) {
      NullVector y{base->dependent[d], {}};
      for (const auto& [r, x] : residue[d]) {
        if (fmpz_is_zero(x.v)) continue;
        if (!fmpq_reconstruct_fmpz(q, x.v, modulus.v)) {
          lifted = false;
          break;
        }
        Rational c;
        fmpq_get_mpq(c.backend().data(), q);
        y.coef.emplace_back(r, c);
      }
      lifted = lifted && verifies(y, rows);
      if (lifted) out.push_back(std::move(y));
    }
    fmpq_clear(q);
    if (lifted) {
      rank = base->rank;
      verified += static_cast<long>(out.size());
      return out;
    }
  }
  throw reference::NotExactHere("the left null space of " + what + " did not lift to rationals that verify within " +
                                std::to_string(kPrimes) + " primes (about " + std::to_string(kPrimes * 62) + " bits)");
}

/// A constraint row: x-part · x = g(u), g over the jets (key d·m + i: d/dt^d f_i).
struct Constraint {
  QRow x;
  QRow g;
};

/// Σ c_k · rows_k (sparse, exact).
QRow combine(const std::vector<std::pair<const QRow*, Rational>>& terms) {
  std::map<long, Rational> sum;
  for (const auto& [row, c] : terms)
    for (const auto& [j, v] : *row) sum[j] += c * v;
  QRow out;
  for (const auto& [j, v] : sum)
    if (v != 0) out.emplace_back(j, v);
  return out;
}

}  // namespace

dcad::Solution<Rational> solve_dae_sparse(const io::DaeCase& c) {
  const std::size_t n = c.variables.size(), m = c.equations();
  std::vector<QRow> erows(m), arows(m);
  const auto fill = [&](const std::vector<io::DaeCase::Entry>& entries, const io::QMatrix& dense,
                        std::vector<QRow>& rows) {
    if (!entries.empty() || !c.dense) {
      for (const auto& e : entries)
        if (e.value != 0) rows[static_cast<std::size_t>(e.row)].emplace_back(e.col, e.value);
    } else {
      for (reference::Index i = 0; i < dense.rows(); ++i)
        for (reference::Index j = 0; j < dense.cols(); ++j)
          if (dense(i, j) != 0) rows[i].emplace_back(static_cast<long>(j), dense(i, j));
    }
    for (QRow& r : rows) std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  };
  fill(c.e_entries, c.e, erows);
  fill(c.a_entries, c.a, arows);
  std::vector<char> has_f(m, 0);
  for (std::size_t i = 0; i < m && i < c.f.size(); ++i) has_f[i] = !ex::is_number(c.f[i], 0);
  const long ml = static_cast<long>(m);

  dcad::Solution<Rational> out = reference::pipeline::dae_result(c, Backend::certified);
  out.tower.push_back({static_cast<long>(n), {}});
  std::vector<Constraint> cons;
  std::vector<std::vector<std::size_t>> added;  // per step, indices into cons
  std::set<long> jet_keys;
  std::vector<std::pair<QRow, std::size_t>> conditions;  // Σ coefficient · jet = 0, and the step it came from
  long verified = 0, last_rank = 0;
  bool undecided = false;
  for (std::size_t step = 0; step <= n; ++step) {
    std::vector<QRow> s = erows;  // S = [E; C_k]
    for (const Constraint& k : cons) s.push_back(k.x);
    std::size_t rank = 0;
    const std::vector<NullVector> ys = left_null(s, n, rank, "[E; C_" + std::to_string(step) + "]", verified);
    last_rank = static_cast<long>(rank);
    // the candidates: y_Eᵀ A x = −y_Eᵀ f − y_Cᵀ ġ
    std::vector<Constraint> cand;
    for (const NullVector& y : ys) {
      std::vector<std::pair<const QRow*, Rational>> xs;
      std::map<long, Rational> g;
      for (const auto& [r, q] : y.coef) {
        if (r < m) {
          xs.emplace_back(&arows[r], q);
          if (has_f[r]) g[static_cast<long>(r)] -= q;  // −y_i f_i: the jet (order 0, equation i)
        } else {
          for (const auto& [key, v] : cons[r - m].g) g[key + ml] -= q * v;  // −y_C ġ: each jet one order up
        }
      }
      Constraint k{combine(xs), {}};
      for (const auto& [key, v] : g)
        if (v != 0) k.g.emplace_back(key, v);
      if (k.x.empty() && k.g.empty()) continue;  // nothing new
      cand.push_back(std::move(k));
    }
    if (cand.empty()) {
      out.steps = static_cast<long>(step);
      break;
    }
    // which candidates are new: [C_k; candidates] (C_k independent), the dependent ones' combinations exact
    std::vector<QRow> t;
    for (const Constraint& k : cons) t.push_back(k.x);
    for (const Constraint& k : cand) t.push_back(k.x);
    std::size_t trank = 0;
    const std::vector<NullVector> zs =
        left_null(t, n, trank, "[C_" + std::to_string(step) + "; its candidates]", verified);
    std::vector<char> dependent(cand.size(), 0);
    for (const NullVector& zv : zs) {
      if (zv.own < cons.size()) throw std::logic_error("certified::solve_dae_sparse: the constraints found dependent");
      dependent[zv.own - cons.size()] = 1;
      // its right sides combined: a condition on the sources (0 = 0 where none)
      std::vector<std::pair<const QRow*, Rational>> gs;
      for (const auto& [r, q] : zv.coef) gs.emplace_back(r < cons.size() ? &cons[r].g : &cand[r - cons.size()].g, q);
      const QRow cond = combine(gs);
      if (!cond.empty()) conditions.emplace_back(cond, step);
    }
    std::vector<std::size_t> fresh;
    for (std::size_t i = 0; i < cand.size(); ++i)
      if (!dependent[i]) {
        fresh.push_back(cons.size());
        cons.push_back(cand[i]);
      }
    // the conditions found at this step, decided against f (pipeline/dae.hpp, as the reference decides them)
    for (auto& [cond, at] : conditions) {
      if (at != step) continue;
      for (const auto& e : cond) jet_keys.insert(e.first);
    }
    bool fails = false, open = false;
    for (const auto& [cond, at] : conditions) {
      if (at != step) continue;
      std::string text;
      std::map<std::string, std::pair<Rational, ex::Expr>>
          same;  // identical formulas (two equal sources) summed first, as the reference does
      for (const auto& [key, q] : cond) {
        const std::size_t i = static_cast<std::size_t>(key % ml);
        const long d = key / ml;
        ex::Expr fd = c.f[i];
        for (long k = 0; k < d; ++k) fd = ex::diff(fd, 0);
        auto& entry = same.try_emplace(ex::to_text(fd, {"t"}), Rational(0), fd).first->second;
        entry.first += q;
        const std::string mag = abs(q) == 1 ? "" : Rational(abs(q)).str() + "*";
        text += (text.empty() ? (q < 0 ? "-" : "") : (q < 0 ? " - " : " + ")) + mag + io::source_name(i, d);
      }
      ex::Expr g = ex::number(0);
      for (const auto& [formula, term] : same)
        if (term.first != 0) g = ex::add(g, ex::mul(ex::number(term.first), term.second));
      SourceCondition sc;
      sc.text = text + " = 0";
      if (std::any_of(out.source_conditions.begin(), out.source_conditions.end(),
                      [&](const SourceCondition& o) { return o.text == sc.text; }))
        continue;
      sc.holds = reference::pipeline::vanishes_identically(g, sc.evidence);
      if (sc.holds.yes() && ex::is_number(g, 0) && !same.empty()) sc.evidence = "identical formulas cancel";
      sc.evidence = "found for M_" + std::to_string(step + 1) + "; " + sc.evidence;
      fails = fails || sc.holds.no();
      open = open || sc.holds.unknown();
      out.source_conditions.push_back(sc);
    }
    // an undecided condition leaves the tower undecided from here, unless another of this step fails
    if (open && !fails) undecided = true;
    for (std::size_t k : fresh)
      for (const auto& e : cons[k].g) jet_keys.insert(e.first);
    if (fails) {  // no velocity anywhere on M_k at generic t: M_{k+1} = ∅
      out.tower.push_back({-1, {}});
      out.consistent = false;
      out.steps = static_cast<long>(step + 1);
      break;
    }
    if (fresh.empty()) {
      out.steps = static_cast<long>(step);
      break;
    }
    added.push_back(fresh);
    out.tower.push_back({static_cast<long>(n - cons.size()), {}});
  }
  // the jets used, in the reference's order (derivative order first, then the equation)
  std::map<long, std::size_t> column;
  for (long key : jet_keys) {
    column[key] = n + out.jets.size();
    out.jets.push_back(io::source_name(static_cast<std::size_t>(key % ml), key / ml));
  }
  const auto equation = [&](const Constraint& k) {  // C x − G u = 0
    Equation<Rational> e;
    for (const auto& [j, v] : k.x) e.terms.emplace_back(static_cast<std::size_t>(j), v);
    for (const auto& [key, v] : k.g) e.terms.emplace_back(column.at(key), -v);
    return e;
  };
  for (std::size_t s = 0; s < added.size(); ++s)
    for (std::size_t k : added[s]) out.tower[s + 1].constraints.push_back(equation(cons[k]));
  for (std::size_t i = 0; i < m; ++i)
    if (has_f[i])
      out.source_names.push_back(io::source_name(i, 0) + " = " +
                                 ex::to_text(c.f[i], {c.time_name.empty() ? "t" : c.time_name}));
  const bool certain = !undecided;
  if (out.consistent) {
    out.solution_rank = static_cast<long>(n) - last_rank;
    std::vector<Equation<Rational>> fin;
    for (const Constraint& k : cons) fin.push_back(equation(k));
    out.final_constraints = fin;
    // a square pencil is singular iff its Kronecker form has an L_ε block (as many as L_ηᵀ), which leaves
    // a velocity free on M_c (fast's sparse route argues the same; the dense reference evaluates det)
    if (m == n) out.regular_pencil = out.solution_rank == 0;
  }
  if (!out.consistent && m == n) {  // the pencil's regularity is the sources-free tower's (its directions are these)
    io::DaeCase free = c;
    for (auto& f : free.f) f = ex::number(0);
    const dcad::Solution<Rational> h = solve_dae_sparse(free);
    out.regular_pencil = h.regular_pencil;
    verified += h.decisions.exact_verifications;
  }
  out.decisions.exact_verifications = verified;
  out.certified = certain ? yes : unknown;
  std::ostringstream note;
  note << "certified sparse route (certified/dae_sparse.hpp): the constraints' rows C_{k+1} = [C_k; y_E^T A], every "
          "left null space found "
          "modulo primes near 2^62, lifted to rationals and verified exactly ("
       << verified << " null vectors); no equations of motion at this size (dense N x N)";
  if (!out.consistent && m == n) note << "; regular_pencil from the same tower without the sources";
  if (!certain) note << "; a condition on the sources was not decided (source_conditions)";
  out.note = note.str();
  return out;
}

}  // namespace dcad::certified
