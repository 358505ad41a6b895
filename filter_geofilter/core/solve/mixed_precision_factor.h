// A complex factor of Kt - r I kept in single precision: half the memory of a double one, and
// faster to compute, while the exact pair solve refines its answer with double-precision
// residuals to the same error bound. Each refinement divides the error by roughly
// 1 / (condition x single rounding); where that is not enough (a pole very close to the
// spectrum on a fine mesh), raise_precision() swaps in a double-precision factor.
#pragma once

#include "core/solve/complex_shifted_factor.h"

#include <functional>
#include <memory>
#include <utility>

namespace geofilter {

class MixedPrecisionFactor : public ComplexShiftedFactor {
public:
    using Make = std::function<std::unique_ptr<ComplexShiftedFactor>()>;

    // `make_single` is called now (it analyses); `make_double` only if the precision must rise.
    MixedPrecisionFactor(const Make& make_single, Make make_double)
        : current_(make_single()), make_double_(std::move(make_double)) {}

    std::string name() const override { return current_->name(); }
    double estimated_factorization_bytes() const override { return current_->estimated_factorization_bytes(); }
    void factorize(std::complex<double> r) override {
        current_->factorize(r);
        shift_ = r;
    }
    bool holds(std::complex<double> r) const override { return current_->holds(r); }
    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override { return current_->solve(b); }
    ComplexFactorSize factor_size() const override { return current_->factor_size(); }

    bool raise_precision() override {
        if (!make_double_ || !current_->holds(shift_)) return false;
        current_.reset();  // its memory goes back before the double factor takes twice as much
        current_ = make_double_();
        make_double_ = nullptr;
        current_->factorize(shift_);
        return true;
    }

private:
    std::unique_ptr<ComplexShiftedFactor> current_;
    Make make_double_;
    std::complex<double> shift_;
};

} // namespace geofilter
