// Regression models of Yaqoob 2017 (ch. 5): the model forms, least-squares fits with uncertainties, and model
// selection.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mtcal {

// The model forms the thesis fits to its error components (eq. 5.1-5.57). x is the driving
// variable (distance, time since start, feed, program-generated error ...).
enum class ModelForm {
  Polynomial,    // c0 + c1 x + c2 x^2 + c3 x^3 (degree 1..3)            eq. 5.1-5.3, 5.8, 5.10, 5.45, 5.56
  ExpApproach,   // a - b exp(-c x)                                       eq. 5.4, 5.6, 5.9, 5.14, 5.48
  StretchedExp,  // a + b exp(-c x^d)                                     eq. 5.12 (e_pt2y)
  LogisticLn,    // a - b / (1 + exp(k ln(x / x0)))                       eq. 5.5, 5.47, 5.49, 5.50, 5.53
  Gompertz,      // a exp(-exp(b - c x))                                  eq. 5.13 (e_tt2x, e_spd2x)
  Saturation,    // a x / (b + x)                                         eq. 5.11, 5.15, 5.46, 5.51
  Power,  // a x^b                                                 eq. 5.7 (e_spdy, read as a power, see eq. 5.29)
};

// "polynomial" "exp_approach" "stretched_exp" "logistic_ln" "gompertz" "saturation" "power".
std::string_view to_string(ModelForm f);
std::optional<ModelForm> model_form_from_string(std::string_view s);

// A form with its structural choices. A polynomial's intercept c0 is either free or fixed to
// fixed_intercept (the thesis fixes it to zero for position errors, eq. 5.1-5.2, and frees it
// for thermal errors, section 3.5). fixed_intercept has no meaning for the other forms.
struct ModelSpec {
  ModelForm form = ModelForm::Polynomial;
  int degree = 1;                         // polynomial only, 1..3
  std::optional<double> fixed_intercept;  // polynomial only

  // "polynomial(2)", "polynomial(2, c0=0)", "exp_approach" ...
  std::string label() const;
};

// Parameter names in the order of Model::p: c0..c3 (polynomial, c0 omitted when fixed),
// a b c (exp_approach), a b c d (stretched_exp), a b k x0 (logistic_ln), a b c (gompertz),
// a b (saturation, power).
std::vector<std::string> parameter_names(const ModelSpec& s);

struct Model {
  ModelSpec spec;
  std::vector<double> p;  // as parameter_names(spec)

  // Value at x. At x = 0 the forms that need x >= 0 take their limits as x -> 0+:
  //   logistic_ln: a - b (k > 0), a (k < 0), a - b/2 (k = 0);
  //   power: 0 (b > 0), a (b = 0: x^0 = 1), NaN (b < 0: a pole);
  //   stretched_exp: a + b (d > 0), a + b exp(-c) (d = 0); for d < 0: a (c > 0), a + b (c = 0),
  //   NaN (c < 0: divergent).
  // Outside a form's domain (x < 0 for logistic_ln, power and stretched_exp; x0 <= 0 for
  // logistic_ln) the result is NaN: callers check.
  double operator()(double x) const;
  // Polynomial c0..c3 whatever was fixed (the fixed intercept included).
  std::vector<double> polynomial_coefficients() const;
};

// The smallest x a form accepts (0 for logistic_ln, power and stretched_exp; -inf otherwise).
double domain_lower_bound(ModelForm f);

// Why parameters (from a model file) put a form outside its domain for x >= x_low, or "" when
// they do not: logistic_ln needs x0 > 0 (ln(x / x0)); saturation needs b > 0 and no pole
// x = -b at or above x_low; stretched_exp needs d > 0 (d <= 0 makes x^d singular or constant at
// x = 0, not a stretched exponential); power needs b >= 0 when x_low <= 0 (0^b is a pole for b < 0).
// The fits keep to the same signs (bounds in fit_model).
std::string parameter_domain_problem(const Model& m, double x_low);

// Backward-prediction error, Yaqoob 2017 section 3.8 and Table 5.8: the model fitted to all the
// data predicts back each measured point and the difference |y_i - f(x_i)| is the "prediction
// error" (Table 5.8 columns diff 1..4). The thesis selects "the model with minimum error
// magnitude" without saying how the differences are combined; mtcal ranks by their mean and
// also reports the largest one and the mean relative difference (section 5.7 quotes "within 5 %").
struct BackwardPrediction {
  std::vector<double> abs_diff;  // |y_i - f(x_i)| per point, input order
  double mean = 0.0;             // mean of abs_diff: the ranking criterion
  double max = 0.0;
  double mean_relative = 0.0;  // mean of |y_i - f(x_i)| / |y_i| over points with y_i != 0; NaN if none
};
BackwardPrediction backward_prediction(const Model& m, std::span<const double> x, std::span<const double> y);

struct FitResult {
  Model model;
  bool converged = false;
  std::string message;  // why it did not converge, or ""
  std::vector<double>
      stddev;  // standard uncertainty per parameter; NaN where not identifiable, at a bound, or dof == 0
  std::vector<double> covariance;  // p x p row-major: sigma^2 (J^T J)^-1 at the solution over the parameters
                                   // inside their bounds; NaN if singular and in the rows/columns of bound ones
  bool identifiable = true;        // J^T J of full rank at the solution and every parameter identified
  // Per parameter: left on the bound that keeps the form in its domain (x0, b, d > 0; see
  // fit_model): a boundary solution, not an interior optimum, so no covariance (stddev NaN).
  std::vector<bool> at_bound;
  // Per parameter: false where the data do not determine it: its Jacobian column is zero or
  // negligible (a 100 % change of the parameter moves the fitted values by less than 1e-9 of
  // the data's size), or the parameters are collinear. stddev NaN.
  std::vector<bool> identified;
  double rss = 0.0;             // sum of squared residuals
  double sigma = 0.0;           // sqrt(rss / dof); NaN when dof == 0
  int dof = 0;                  // n - p
  double r_squared = 0.0;       // 1 - rss / sum (y - mean y)^2
  double aicc = 0.0;            // corrected Akaike criterion n ln(rss/n) + 2p + 2p(p+1)/(n-p-1); NaN if n-p-1 <= 0
  BackwardPrediction backward;  // section 3.8 (in-sample)
  // Leave-one-out cross-validation: each point predicted by the model refitted without it.
  std::optional<double> loocv_rmse;  // sqrt(mean of squared leave-one-out errors); none if n - 1 < p or a refit fails
  std::vector<double> loocv_errors;  // y_i - f_(-i)(x_i), input order (empty without loocv_rmse)
  // How the leave-one-out errors were obtained (see FitOptions::loocv_refit_max): "refit" (n
  // refits), "hat_matrix" (polynomials above the limit: e_i = r_i / (1 - h_ii), the exact
  // identity of linear least squares), "linearised" (nonlinear forms above the limit: the same
  // formula with the Jacobian at the solution, i.e. one Gauss-Newton step of each refit); "" without.
  std::string loocv_method;
};

struct FitOptions {
  bool loocv = true;
  // Up to this many points every leave-one-out model is refitted (n fits: quadratic cost for
  // polynomials, n Levenberg-Marquardt runs with their start grid for the nonlinear forms);
  // above it the hat-matrix formula is used (exact for polynomials, linearised otherwise).
  std::size_t loocv_refit_max = 100;
};

// Least squares of spec to (x, y). Polynomials are solved exactly (QR); the other forms by
// Ceres' Levenberg-Marquardt from the best point of a grid over their nonlinear parameters,
// where the linear ones (a, b) are solved exactly for each grid point (variable projection), so
// that no user start is needed. Throws InputError (field "x"/"y") for fewer points than
// parameters, different lengths, non-finite values or x outside the form's domain.
FitResult fit_model(const ModelSpec& spec, std::span<const double> x, std::span<const double> y,
                    const FitOptions& options = {});

// The forms tried for the list "all": polynomials of degree 1..3 with a free intercept, with the
// intercept fixed at 0, and the six nonlinear forms.
std::vector<ModelSpec> all_model_specs();
// "all" or a comma list of labels ("polynomial(2)", "polynomial(1,c0=0)", "exp_approach" ...),
// InputError naming source for an unknown one.
std::vector<ModelSpec> parse_model_specs(const std::string& list, const std::string& source);

// Every spec fitted (those that cannot be fitted: fewer points than parameters, x out of the
// domain, no convergence, are listed with a reason), ranked two ways.
struct ModelComparison {
  std::vector<FitResult> fits;
  struct Skipped {
    ModelSpec spec;
    std::string reason;
  };
  std::vector<Skipped> skipped;
  std::vector<std::size_t> by_backward;  // indices into fits, smallest mean backward-prediction error first
  std::vector<std::size_t> by_loocv;     // smallest leave-one-out RMSE first (fits without one last)
};
ModelComparison compare_models(const std::vector<ModelSpec>& specs, std::span<const double> x,
                               std::span<const double> y);

}  // namespace mtcal
