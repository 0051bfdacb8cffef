// One Problem of exact data from any input form (../shared/CONTRACT.md): a linear case file
// (`dirac`, `pontryagin`, `constrained`), an expression-form case (`lagrangian`) or a SPICE netlist.
// Read once, dispatched once: every route of every backend starts from a Problem.
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/io/dae_case.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "dcad/io/netlist.hpp"
#include "dcad/reference/system.hpp"

#include <string>
#include <variant>
#include <vector>

namespace dcad::io {

enum class Form {
  linear,      ///< a `dirac`, `pontryagin` or `constrained` case (CEF §2, §5, §6)
  netlist,     ///< an LC or RLC netlist (CEF §6, YM §4)
  expression,  ///< the expression form: a Lagrangian system by formulas (YM §4–§6, V §3)
  dae,         ///< a linear DAE E ẋ = A x + f(t) (CEF (1.6); CONTRACT "Linear and implicit DAEs")
  implicit,    ///< an implicit DAE φ(t, x, ẋ) = 0 affine in ẋ (CEF (1.6)), held in `expression` (system.implicit)
};

/// A circuit: its deck, and the names of its state's variables (q_*, v_*, p_* per branch, CONTRACT) as the `pontryagin`
/// case it stands for names them (io::netlist_case without the dense matrices).
struct CircuitCase {
  Netlist deck;
  CaseFile names;
};

/// The expression form: a Lagrangian system by formulas (YM §4–§6, V §3).
struct ExpressionCase {
  LagrangianCase c;
};

/// The implicit form φ(t, x, ẋ) = 0 (CEF (1.6)), read into a LagrangianCase whose `system.implicit` is set.
struct ImplicitCase {
  LagrangianCase c;
};

/// One problem: exactly one input form, whose alternative is the form (no tag beside the data that could disagree
/// with it).  Read by read_problem, parse_netlist, parse_case, or built in code by io::problem(…); `file` names it in
/// every message.
struct Problem {
  std::string file;  ///< where it was read from (names every message)
  /// In Form's order: a linear case, a circuit, the expression form, a linear DAE, the implicit form.
  std::variant<CaseFile, CircuitCase, ExpressionCase, DaeCase, ImplicitCase> input;

  Form form() const { return static_cast<Form>(input.index()); }
  /// Form::linear: the case; Form::netlist: the circuit's variable names.  std::logic_error for another form.
  const CaseFile& linear() const;
  CaseFile& linear();
  /// Form::netlist.
  const Netlist& netlist() const;
  Netlist& netlist();
  /// Form::expression or Form::implicit (its system is `implicit`).
  const LagrangianCase& expression() const;
  LagrangianCase& expression();
  /// Form::dae.
  const DaeCase& dae() const;
  DaeCase& dae();

  /// The state's variable names, in order: x of a linear case, (q, v, p) of a circuit or a Lagrangian system.
  std::vector<std::string> variables() const;
  /// The case's `name`, the netlist's title, or "".
  std::string name() const;
  /// The reader's warnings (a netlist's ignored cards, non-physical values), each naming file:line.
  const std::vector<std::string>& warnings() const;
};

/// Problems built in code, one call per input form, each with every part a case file gets (final constraints,
/// (5.12), classes, adapted; the DAE's index; the pointwise values) and validated by every solve as a file's is.
/// A `dirac`, `pontryagin` or `constrained` case (CEF §2, §5, §7).
Problem problem(CaseFile c);
/// A circuit's deck (its `circuit`, `rlc`, waveforms … as the reader makes them), its variables named from it.
Problem problem(Netlist deck);
/// Your own exact linear Dirac system (D, E) (CEF §5: D as the rows of a basis, E = ½ xᵀ H x + gᵀ x + c), the
/// `dirac` form `basis`; `variables` default to x1 … xN.
Problem problem(const reference::LinearSystem<Rational>& s, std::vector<std::string> variables = {},
                std::string name = "");
/// A linear DAE E ẋ = A x + f(t) (CEF (1.6)); only `variables`, `e`, `a` are required (f is 0 where absent).
Problem problem(DaeCase c);
/// A Lagrangian system by formulas (YM §4–§6, V §3): Form::expression; an implicit DAE φ(t, x, ẋ) = 0 where
/// `system.implicit` (Form::implicit).
Problem problem(LagrangianCase c);

/// A Problem built in code held to what the readers guarantee (issue 45 §5): sizes of every matrix and
/// vector, unique non-empty names, node, source and variable indices in range, complete formulas.
/// InputError naming the field, what was expected and what was found.  Every twin's solve (and every
/// dcad::api entry point) calls it first, so a malformed problem is never solved as another one.
void validate(const Problem& p);

/// Any input file: a netlist by its extension (.cir, .sp, .net, .spice, .ckt), else a JSON case in
/// the expression form or a linear one — the JSON is read once.  InputError for bad input.  `options`
/// apply to a netlist (its dialect).
Problem read_problem(const std::string& file, const ReadOptions& options = {});

/// A netlist given as text; `name` stands for the file in messages, and `.include`/`.lib` paths are
/// taken relative to `directory`.
Problem parse_netlist(const std::string& text, const std::string& name = "netlist.cir",
                      const std::string& directory = ".", const ReadOptions& options = {});

/// A JSON case (linear or expression form) given as text; `name` stands for the file in messages.
Problem parse_case(const std::string& text, const std::string& name = "case.json");

/// f() with a linear case's library preconditions (std::invalid_argument: not a Dirac structure, a
/// degenerate form …) as InputError naming the file and the case's form (`/pontryagin`,
/// `/constrained` or the `dirac` form's path).  Every twin's solve reports its input this way.
template <class F>
auto at_input(const CaseFile& c, F f) {
  try {
    return f();
  } catch (const InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InputError(c.file + ": " +
                     (c.has_pontryagin    ? "/pontryagin"
                      : c.has_constrained ? "/constrained"
                                          : c.dirac.path) +
                     ": " + e.what());
  }
}

}  // namespace dcad::io
