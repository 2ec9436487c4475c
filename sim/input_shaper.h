// Input shapers (MODEL.md §5, "Input shaping"): a sequence of impulses that
// the move is convolved with, so that the vibration of a lightly damped mode
// excited by one part of the move is cancelled by the vibration the later
// parts excite. The six shapers of Klipper's resonance compensation
// (docs/Resonance_Compensation.md of Klipper), each a closed form in the
// mode's frequency f (Hz) and damping ratio ζ:
//
//   K = exp(−ζπ/√(1−ζ²)), T_d = 1/(f·√(1−ζ²)) (the damped period)
//   ZV    A ∝ [1, K],                          t = [0, ½]·T_d
//         (Singer & Seering 1990, "Preshaping command inputs to reduce system
//         vibration", J. Dyn. Sys. Meas. Control 112(1))
//   ZVD   A ∝ [1, 2K, K²],                     t = [0, ½, 1]·T_d  (idem)
//   MZV   A ∝ [1 − 1/√2, (√2 − 1)·K', (1 − 1/√2)·K'²], K' = K^(3/4),
//         t = [0, 3/8, 3/4]·T_d: three impulses 135° apart whose vectors
//         close at f (the vector-diagram construction of Singhose, Seering &
//         Singer 1990, "Shaping inputs to reduce vibration: a vector diagram
//         approach", ICRA), Klipper's "MZV"
//   EI    A ∝ [(1+V)/4, (1−V)·K/2, (1+V)·K²/4], t = [0, ½, 1]·T_d
//   2HUMP_EI  A ∝ [a, (½−a)·K, (½−a)·K², a·K³], t = [0, ½, 1, 3/2]·T_d,
//         a = (3X² + 2X + 3V²)/(16X), X = (V²(√(1−V²) + 1))^(1/3)
//   3HUMP_EI  A ∝ [a, b·K, (1−2a−2b)·K², b·K³, a·K⁴], t = [0, ½, 1, 3/2, 2]·T_d,
//         a = (1 + 3V + 2√(2V(V+1)))/16, b = (1−V)/4
//   (the extra-insensitive shapers: Singhose, Derezinski & Singer 1996,
//   "Extra-insensitive input shapers for controlling flexible spacecraft",
//   J. Guidance, Control, and Dynamics 19(2); their undamped closed forms,
//   each impulse scaled by K per half period for ζ > 0, as Klipper does),
// with the vibration tolerance V = 0.05 (5 %, the EI family's design: EI
// leaves V at f and keeps the vibration at or below it over about ±20 % of
// f, Klipper's table). Amplitudes are normalised to sum to 1, so a shaped
// move ends where the unshaped one does, later by the shaper's duration.
#ifndef SIM_INPUT_SHAPER_H_
#define SIM_INPUT_SHAPER_H_

#include <string>
#include <vector>

namespace axis {

enum class ShaperType { kNone, kZV, kMZV, kZVD, kEI, k2HumpEI, k3HumpEI };

// The EI family's vibration tolerance V (fraction of the unshaped
// vibration).
constexpr double kShaperVibrationTolerance = 0.05;

// An input shaper: impulses of `amplitudes` (positive, summing to 1) at
// `times` (s, ascending, the first 0), designed for a mode of `frequency`
// (Hz) and `damping` (ζ). The none shaper has one impulse of 1 at 0.
struct InputShaper {
  ShaperType type = ShaperType::kNone;
  double frequency = 0.0;  // Hz, > 0 unless none
  double damping = 0.0;    // ζ in [0, 1)
  std::vector<double> amplitudes = {1.0};
  std::vector<double> times = {0.0};

  // s from the first impulse to the last: what the shaper adds to a move.
  double Duration() const { return times.back(); }
};

// The shaper `type` for a mode of `frequency` Hz and damping ratio `damping`
// (the closed forms above). Throws std::invalid_argument for a frequency
// that is not finite and positive or a damping outside [0, 1) (unless
// type is kNone, which takes neither).
InputShaper MakeInputShaper(ShaperType type, double frequency, double damping);

// The residual vibration the shaper `s` leaves on a second-order mode of
// natural frequency `frequency` Hz and damping `damping` after its last
// impulse, relative to the unshaped impulse (Singer & Seering 1990, eq. 4):
//   V = e^(−ζω t_N) · |Σ A_i e^(ζω t_i) e^(jω_d t_i)|,
// ω = 2πf, ω_d = ω√(1−ζ²). 1 for the none shaper; 0 at a ZV, ZVD, MZV or
// (undamped) 2HUMP_EI shaper's own design point, V at EI's and 3HUMP_EI's.
// Throws std::invalid_argument as MakeInputShaper.
double ShaperVibration(const InputShaper& s, double frequency, double damping);

// "none", "ZV", "MZV", "ZVD", "EI", "2HUMP_EI", "3HUMP_EI" (Klipper's names).
std::string ShaperName(ShaperType type);

// The type named `name` (ShaperName's, case-insensitive); false if none is.
bool ParseShaperType(const std::string& name, ShaperType* type);

// The names ParseShaperType accepts, in ShaperType order.
const std::vector<std::string>& ShaperNames();

}  // namespace axis

#endif  // SIM_INPUT_SHAPER_H_
