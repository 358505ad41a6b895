#include "spectral.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace geofilter::reference {

Spectrum dense_spectrum(const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& mass) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(stiffness, Eigen::MatrixXd(mass.asDiagonal()));
    return {eig.eigenvalues(), eig.eigenvectors(), mass};
}

Eigen::VectorXd generalized_eigenvalues(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(a, b, Eigen::EigenvaluesOnly | Eigen::Ax_lBx);
    return eig.eigenvalues();
}

Spectrum spectrum_of(const Mesh& mesh) {
    const Laplacian l = cotan_laplacian(mesh.points, mesh.triangles);
    return dense_spectrum(Eigen::MatrixXd(l.stiffness), l.mass);
}

Points spectral_filter(const Spectrum& s, const Points& p, const TransferFunction& g) {
    const Eigen::RowVector3d c = (s.mass.transpose() * p) / s.mass.sum();
    const Eigen::MatrixXd centred = p.rowwise() - c;
    Eigen::VectorXd gains(s.eigenvalues.size());
    for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = g(std::max(0.0, s.eigenvalues[i]));
    const Eigen::MatrixXd modal = s.eigenvectors.transpose() * (s.mass.asDiagonal() * centred);
    Eigen::MatrixXd out = s.eigenvectors * (gains.asDiagonal() * modal);
    out.rowwise() += c;
    return out;
}

} // namespace geofilter::reference
