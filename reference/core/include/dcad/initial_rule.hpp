// dcad::InitialRule — where a netlist starts (CONTRACT "Circuit initial state"), the one enum the pipeline and
// dcad::api (api::Initial) share.
#pragma once

namespace dcad {

/// As the deck's `.tran` says (uic, or the DC operating point without it; no `.tran`: uic), or forced by
/// `--initial op|uic`.
enum class InitialRule { deck, op, uic };

}  // namespace dcad
