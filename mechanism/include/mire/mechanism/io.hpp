#pragma once
// Files of the identification (doc/file-formats.md): poses.csv (+ its covariance side file),
// joints.csv, straight-line joint records (criterion V3), mechanism parameter YAML.
// Every reader validates the whole file before returning and throws std::runtime_error
// whose message names the file and line ("path:line: ...") and what is wrong.
#include <Eigen/Core>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

// ---- poses.csv --------------------------------------------------------------------------
// Header (doc/file-formats.md, extra columns allowed):
//   pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,
//   sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px
// Covariance of each pose: the `total` part of the side file when given, written by
// `mire measure` (header pose_id,part,row,tx,ty,tz,rx,ry,rz; 6 rows per part; SI), else the
// σ columns as a diagonal (mm → m, deg → rad) when all six are > 0, else none.
// Errors: missing column, duplicate pose id, non-finite value, negative σ, a pose missing
// from the side file.
struct PoseRow {
  PoseObservation observation;  // joints empty
  int line = 0;                 // line in poses.csv
};
std::vector<PoseRow> readPosesCsv(const std::filesystem::path& poses_csv,
                                  const std::optional<std::filesystem::path>& covariance_csv = {});

// ---- joints.csv -------------------------------------------------------------------------
// Header pose_id,q1_rad,...,qN_rad (N = joint_count; extra columns allowed). Errors:
// missing column, duplicate id, non-finite value.
struct JointRow {
  std::string pose_id;
  Eigen::VectorXd joints;
  int line = 0;
};
std::vector<JointRow> readJointsCsv(const std::filesystem::path& joints_csv, int joint_count = 4);
// The mechanism's own columns (Mechanism::jointColumnNames(): q<i>_rad or q<i>_m).
std::vector<JointRow> readJointsCsv(const std::filesystem::path& joints_csv,
                                    const std::vector<std::string>& joint_columns);
// Writes joints.csv atomically (17 significant digits).
void writeJointsCsv(const std::filesystem::path& joints_csv, const std::vector<std::string>& ids,
                    const std::vector<Eigen::VectorXd>& joints);
void writeJointsCsv(const std::filesystem::path& joints_csv, const std::vector<std::string>& ids,
                    const std::vector<Eigen::VectorXd>& joints, const std::vector<std::string>& joint_columns);

// Pairs poses and joints by id. A pose without joints is an error naming the poses file
// and line; joints rows without a pose are returned in `unused_joint_ids` (e.g. poses that
// `mire measure` could not measure).
struct ObservationSet {
  std::vector<PoseObservation> poses;
  std::vector<std::string> unused_joint_ids;
};
ObservationSet readObservations(const std::filesystem::path& poses_csv, const std::filesystem::path& joints_csv,
                                const std::optional<std::filesystem::path>& covariance_csv = {}, int joint_count = 4);
ObservationSet readObservations(const std::filesystem::path& poses_csv, const std::filesystem::path& joints_csv,
                                const std::optional<std::filesystem::path>& covariance_csv,
                                const std::vector<std::string>& joint_columns);

// ---- lines.csv (straight-line motions, criterion V3, paper §6.1) ---------------------------
// Header line_id,q1_rad,...,qN_rad; one row per recorded point, points in motion order,
// rows of a line contiguous or not (grouped by line_id in first-appearance order).
struct LineRecord {
  std::string line_id;
  std::vector<Eigen::VectorXd> joints;
};
std::vector<LineRecord> readLinesCsv(const std::filesystem::path& lines_csv, int joint_count = 4);
std::vector<LineRecord> readLinesCsv(const std::filesystem::path& lines_csv,
                                     const std::vector<std::string>& joint_columns);
void writeLinesCsv(const std::filesystem::path& lines_csv, const std::vector<LineRecord>& lines);
void writeLinesCsv(const std::filesystem::path& lines_csv, const std::vector<LineRecord>& lines,
                   const std::vector<std::string>& joint_columns);

// ---- mechanism parameter YAML (parameters_yaml.cpp) -------------------------------------
// A flat YAML mapping, any YAML syntax (support/yaml.hpp; OpenCV's "%YAML:1.0" too):
//   <parameter name>: <value, SI>          e.g.  R: 0.22
//   sigma_<parameter name>: <σ, SI>        identified files
//   <metadata key>: <text>                 model, variant, external_form, ... (see below)
struct ParameterFileEntry {
  std::string key;
  std::string text;  // the value as written (quotes removed)
  int line = 0;
};
struct ParameterFile {
  std::filesystem::path path;
  std::vector<ParameterFileEntry> entries;  // file order, keys unique

  const ParameterFileEntry* find(const std::string& key) const;
  // Numeric value of `key`; throws "path:line: key: 'x' is not a finite number".
  double number(const ParameterFileEntry& entry) const;
  std::string where(const ParameterFileEntry& entry) const;  // "path:line"
};
// Throws naming path:line on a syntax error, an empty file, a duplicate key or a value that is
// not a single scalar.
ParameterFile readParameterFile(const std::filesystem::path& path);

// The file's `model:` value, or empty without one; a relative mechanism description path
// (`model: identified_mechanism.yaml`) is taken from the file's own folder.
std::string parameterFileModel(const ParameterFile& file);

// Text keys a parameter file may hold besides parameters and sigma_<name>.
const std::vector<std::string>& parameterFileMetadataKeys();

// Copies the file's values into `parameters` (by name). Every key must be a parameter of
// `parameters`, a sigma_<parameter>, a metadata key, or listed in `also_allowed` (accepted
// and ignored); otherwise throws "path:line: unknown parameter name 'x' (did you mean 'y'?)".
// Every parameter of `parameters` must be given, except those named in `may_default` (which
// keep their value when absent): a missing one is an error naming them all. Non-finite values
// are errors, and so is an angle (unit rad) of magnitude over 2π, which is degrees typed by
// mistake. Returns the names that were set.
std::vector<std::string> applyParameterFile(const ParameterFile& file, ParameterSet& parameters,
                                            const std::vector<std::string>& also_allowed = {},
                                            const std::vector<std::string>& may_default = {});

// Writes `parameters` as plain YAML that YAML 1.1 readers (PyYAML) read too (name: value, SI,
// 17 significant digits; one comment line per parameter with its unit, its
// human value in mm/deg and whether it was fixed), then sigma_<name> for every σ > 0 in
// `sigma` (same order as `parameters`, may be empty), preceded by `metadata` (key, text)
// and a '#' header `comment`. Atomic (support::writeFileAtomically).
void writeParameterFile(const std::filesystem::path& path, const ParameterSet& parameters,
                        const Eigen::VectorXd& sigma = {},
                        const std::vector<std::pair<std::string, std::string>>& metadata = {},
                        const std::string& comment = {});
std::string parameterFileString(const ParameterSet& parameters, const Eigen::VectorXd& sigma = {},
                                const std::vector<std::pair<std::string, std::string>>& metadata = {},
                                const std::string& comment = {});

}  // namespace mire::mechanism
