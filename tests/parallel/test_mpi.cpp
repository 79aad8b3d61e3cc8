// The mesodpd program under mpirun (CTest label mpi): results that do not depend on the rank count,
// conservation under decomposition, restarts on another rank count, refused decompositions, and a box
// with bounded axes (tests/parallel/bounded_run.cpp).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "octahedra_data.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

std::string read_all(const fs::path& path) { return mesodpd::test::read_file(path); }

fs::path fresh_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_mpi" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Result {
  int code = -1;
  std::string out, err;
};

// `mpirun -np N mesodpd ARGS` in `dir` (or another `program`). Ranks yield when idle, so more ranks than
// cores stay usable.
Result mpirun(const fs::path& dir, int ranks, const std::string& args, int threads = 1,
              const std::string& program = mesodpd::test::mesodpd_bin()) {
  const std::string cmd = "cd '" + dir.string() + "' && OMP_NUM_THREADS=" + std::to_string(threads) +
                          " OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                          "OMPI_MCA_mpi_yield_when_idle=1 OMPI_MCA_rmaps_base_oversubscribe=1 timeout 300 '" +
                          std::string(MESODPD_MPIEXEC) + "' --oversubscribe -np " + std::to_string(ranks) + " '" +
                          program + "' " + args + " > mpi_stdout.txt 2> mpi_stderr.txt";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_all(dir / "mpi_stdout.txt");
  r.err = read_all(dir / "mpi_stderr.txt");
  return r;
}

// An 8 x 8 x 8 standard fluid (rho = 3, a = 25, gamma = 4.5, dt = 0.04): 8 cells per axis, so every
// grid below leaves each rank at least 4 cells thick. `extra` adds or overrides tables.
std::string fluid_config(const std::string& extra) {
  return "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 2026\n\n"
         "[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
         "[pair]\na = 25.0\ngamma = 4.5\n\n[integrator]\ndt = 0.04\n\n"
         "[run]\nsteps = 2000\n\n" +
         extra;
}

const char* kOutput =
    "[output]\nthermo_every = 100\nprogress = false\n\n"
    "[output.dump]\nevery = 500\nfields = [\"id\", \"species\", \"position\", \"velocity\", \"force\", \"image\"]\n\n"
    "[analysis.msd]\nevery = 100\n\n"
    "[analysis.fields]\nbins = [4, 1, 8]\nevery = 50\ncentre = \"z\"\n";

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string grid_table(int px, int py, int pz) {
  return "[parallel]\ngrid = [" + std::to_string(px) + ", " + std::to_string(py) + ", " + std::to_string(pz) + "]\n\n";
}

std::vector<std::vector<double>> thermo_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// Cells mode, 2,000 steps, on 1, 2 (2x1x1), 4 (2x2x1) and 8 (2x2x2) ranks and 2 ranks x 2 threads: with 2x2x2 every face, edge
// and corner of a domain is shared with another rank. Checkpoint (positions, velocities, forces, images in
// id order), thermo.csv, trajectory and MSD must be byte-identical to the single-rank run.
TEST(Mpi, TrajectoriesAreBitIdenticalOnOneTwoFourAndEightRanks) {
  const fs::path dir = fresh_dir();
  struct Case {
    int ranks;
    std::array<int, 3> grid;
  };
  const std::vector<Case> cases = {{1, {1, 1, 1}}, {2, {2, 1, 1}}, {4, {2, 2, 1}}, {8, {2, 2, 2}}};
  for (const Case& c : cases) {
    const std::string name = fmt::format("r{}", c.ranks);
    write(dir / (name + ".toml"), fluid_config(grid_table(c.grid[0], c.grid[1], c.grid[2]) + kOutput));
    const Result r = mpirun(dir, c.ranks, "run " + name + ".toml --out " + name);
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find(std::to_string(c.ranks) + " rank(s)"), std::string::npos) << r.out;
  }
  // Hybrid: 2 ranks with 2 OpenMP threads each.
  write(dir / "hybrid.toml", fluid_config(grid_table(2, 1, 1) + kOutput));
  const Result hybrid = mpirun(dir, 2, "run hybrid.toml --out hybrid", 2);
  ASSERT_EQ(hybrid.code, 0) << hybrid.out << hybrid.err;
  EXPECT_NE(hybrid.out.find("2 thread(s) per rank"), std::string::npos) << hybrid.out;
  for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "msd.csv", "fields.vti", "fields.csv"})
    EXPECT_EQ(read_all(dir / "hybrid" / file), read_all(dir / "r1" / file)) << file << " differs with 2 x 2 threads";
  // Without mpirun the program is a one-rank run too, and gives the same files.
  const std::string plain = "cd '" + dir.string() + "' && OMP_NUM_THREADS=2 timeout 300 '" +
                            mesodpd::test::mesodpd_bin() + "' run r1.toml --out plain > plain.txt 2>&1";
  ASSERT_EQ(std::system(plain.c_str()), 0) << read_all(dir / "plain.txt");
  for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "msd.csv", "fields.vti", "fields.csv"})
    EXPECT_EQ(read_all(dir / "plain" / file), read_all(dir / "r1" / file)) << file << " differs without mpirun";
  for (const Case& c : cases) {
    if (c.ranks == 1) continue;
    const std::string name = fmt::format("r{}", c.ranks);
    for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "msd.csv", "fields.vti", "fields.csv"})
      EXPECT_EQ(read_all(dir / name / file), read_all(dir / "r1" / file)) << file << " differs on " << c.ranks << " ranks";
  }
  // The particles really crossed domains: the mean squared displacement at the end exceeds the square of
  // a domain's width (4) several times over.
  std::ifstream msd(dir / "r8" / "msd.csv");
  std::string line, last;
  while (std::getline(msd, line))
    if (!line.empty()) last = line;
  // msd.csv columns: time,msd
  const double final_msd = std::stod(last.substr(last.find(',') + 1));
  EXPECT_GT(final_msd, 3 * 16.0) << last;
}

// Momentum is conserved to round-off and no particle is lost or duplicated after many migrations.
TEST(Mpi, MomentumAndParticlesAreConservedUnderDecomposition) {
  const fs::path dir = fresh_dir();
  write(dir / "c.toml", fluid_config(grid_table(2, 2, 1) + kOutput));
  const Result r = mpirun(dir, 4, "run c.toml --out out");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto rows = thermo_rows(dir / "out" / "thermo.csv");
  ASSERT_EQ(rows.size(), 21u);
  for (const auto& row : rows)
    for (int k = 10; k < 13; ++k) EXPECT_LT(std::abs(row[static_cast<std::size_t>(k)]), 1e-9) << "step " << row[0];
  // The last dump frame holds every id exactly once.
  std::ifstream in(dir / "out" / "trajectory.lammpstrj");
  std::string line;
  std::vector<std::string> frame;
  while (std::getline(in, line)) {
    if (line == "ITEM: TIMESTEP") frame.clear();
    frame.push_back(line);
  }
  ASSERT_GT(frame.size(), 9u);
  EXPECT_EQ(frame[1], "2000");
  std::set<long> ids;
  for (std::size_t k = 9; k < frame.size(); ++k) ids.insert(std::stol(frame[k]));
  EXPECT_EQ(ids.size(), 1536u);
  EXPECT_EQ(frame.size() - 9, 1536u);
  EXPECT_EQ(*ids.begin(), 1);  // LAMMPS dump ids count from 1
  EXPECT_EQ(*ids.rbegin(), 1536);
}

// Checkpoints written on N ranks continue on M ranks exactly as an uninterrupted single-rank run.
TEST(Mpi, RestartOnADifferentRankCount) {
  const fs::path dir = fresh_dir();
  write(dir / "c.toml", fluid_config(kOutput));
  ASSERT_EQ(mpirun(dir, 1, "run c.toml --out whole").code, 0);
  ASSERT_EQ(mpirun(dir, 2, "run c.toml --out a --steps 1000").code, 0);
  fs::copy_file(dir / "a" / "checkpoint.mdpd", dir / "a1000.mdpd");
  const Result r = mpirun(dir, 4, "run c.toml --out a --restart a1000.mdpd");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  ASSERT_EQ(mpirun(dir, 4, "run c.toml --out b --steps 1000").code, 0);
  fs::copy_file(dir / "b" / "checkpoint.mdpd", dir / "b1000.mdpd");
  ASSERT_EQ(mpirun(dir, 1, "run c.toml --out b --restart b1000.mdpd").code, 0);
  for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "fields.vti", "fields.csv"}) {
    EXPECT_EQ(read_all(dir / "a" / file), read_all(dir / "whole" / file)) << file << " (2 -> 4 ranks)";
    EXPECT_EQ(read_all(dir / "b" / file), read_all(dir / "whole" / file)) << file << " (4 -> 1 rank)";
  }
}

// Chains (harmonic bonds, angles) and branched FENE molecules in a solvent: bonds cross rank boundaries,
// partners are found as ghosts, ghost forces go back to their owners. Same bits as one rank on 2 and 4
// ranks, on 2 ranks x 2 threads, with Verlet lists, and after a restart on another rank count.
std::string bonds_config(const std::string& extra) {
  return "[system]\nbox = [9.0, 9.0, 9.0]\nkT = 1.0\nseed = 2026\n\n"
         "[[species]]\nname = \"A\"\n\n[[species]]\nname = \"W\"\ndensity = 2.0\n\n"
         "[pair]\na = 25.0\ngamma = 4.5\n\n"
         "[[bond_type]]\nname = \"spring\"\nstyle = \"harmonic\"\nk = 20.0\nr0 = 0.6\n\n"
         "[[bond_type]]\nname = \"fene\"\nstyle = \"fene\"\nk = 10.0\nrmax = 1.9\n\n"
         "[[angle_type]]\nname = \"bend\"\nk = 2.0\ntheta0 = 20.0\n\n"
         "[[molecule]]\nname = \"chain\"\nsequence = \"A10\"\nbond_type = \"spring\"\nangle_type = \"bend\"\n"
         "count = 60\nbond_length = 0.6\n\n"
         "[[molecule]]\nname = \"lipid\"\nsequence = \"W2(A4)2\"\nbond_type = \"fene\"\nangle_type = \"bend\"\n"
         "count = 20\nbond_length = 0.6\n\n"
         "[bonds]\nreach = 2.0\n\n[integrator]\ndt = 0.02\n\n[run]\nsteps = 120\n\n"
         "[output]\nthermo_every = 20\nprogress = false\n\n"
         "[output.dump]\nevery = 40\nfields = [\"id\", \"mol\", \"position\", \"velocity\", \"image\"]\n\n"
         "[analysis.stress_profile]\naxis = \"z\"\nbins = 9\nstart = 20\nevery = 20\nblocks = 2\n\n" +
         extra;
}

// Dihedrals (a LAMMPS data file of 27 jittered octahedra, tests/octahedra_data.hpp) in a DPD thermostat:
// the octahedra on the rank boundaries have dihedrals whose atoms are owned by both ranks, found as
// ghosts, their forces sent home. Same bits on 1, 2 and 4 ranks and after a restart on another count.
TEST(Mpi, DihedralsGiveTheSameBitsOnOneTwoAndFourRanksAndAfterARestart) {
  const fs::path dir = fresh_dir();
  std::vector<std::array<double, 3>> centres;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) centres.push_back({1.5 + 3.0 * i, 1.5 + 3.0 * j, 1.5 + 3.0 * k});
  write(dir / "octahedra.data", mesodpd::test::octahedra_data(centres, 9.0, 0.1));
  const auto config = [&](const std::string& extra) {
    return "[system]\nbox = [9.0, 9.0, 9.0]\nkT = 1.0\nseed = 27\n\n[[species]]\nname = \"V\"\n\n"
           "[pair]\na = 25.0\ngamma = 4.5\n\n[init]\nlammps_data = \"octahedra.data\"\nvelocities = \"maxwell\"\n\n"
           "[[bond_type]]\nname = \"edge\"\nstyle = \"harmonic\"\nk = 50.0\nr0 = 1.4142\n\n"
           "[[dihedral_type]]\nname = \"hinge\"\nk = 3.0\ntheta0 = 20.0\n\n[bonds]\nreach = 2.5\n\n"
           "[integrator]\ndt = 0.01\n\n[run]\nsteps = 100\n\n[output]\nthermo_every = 20\nprogress = false\n\n" +
           extra;
  };
  write(dir / "d1.toml", config(""));
  write(dir / "d2.toml", config(grid_table(2, 1, 1)));
  write(dir / "d4.toml", config(grid_table(2, 2, 1)));
  for (int ranks : {1, 2, 4}) {
    const std::string name = fmt::format("d{}", ranks);
    const Result r = mpirun(dir, ranks, "run " + name + ".toml --out " + name);
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }
  ASSERT_EQ(mpirun(dir, 2, "run d2.toml --out half --steps 50").code, 0);
  fs::copy_file(dir / "half" / "checkpoint.mdpd", dir / "d50.mdpd");
  const Result resumed = mpirun(dir, 4, "run d4.toml --out half --restart d50.mdpd");
  ASSERT_EQ(resumed.code, 0) << resumed.out << resumed.err;
  for (const char* file : {"checkpoint.mdpd", "thermo.csv"})
    for (const char* other : {"d2", "d4", "half"})
      EXPECT_TRUE(read_all(dir / other / file) == read_all(dir / "d1" / file)) << file << " differs in " << other;
}

// (The stress profile, gathered on the root, is compared too: its files are the same bytes.)
TEST(Mpi, BondsGiveTheSameBitsOnOneTwoAndFourRanksAndAfterARestart) {
  const fs::path dir = fresh_dir();
  write(dir / "r1.toml", bonds_config(""));
  write(dir / "r2.toml", bonds_config(grid_table(2, 1, 1)));
  write(dir / "r4.toml", bonds_config(grid_table(2, 2, 1)));
  for (int ranks : {1, 2, 4}) {
    const std::string name = fmt::format("r{}", ranks);
    const Result r = mpirun(dir, ranks, "run " + name + ".toml --out " + name);
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }
  const Result hybrid = mpirun(dir, 2, "run r2.toml --out hybrid", 2);
  ASSERT_EQ(hybrid.code, 0) << hybrid.out << hybrid.err;
  ASSERT_NE(read_all(dir / "r1" / "stress_profile.json").find("tension"), std::string::npos);
  for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "stress_profile.csv", "stress_profile.json"}) {
    for (const char* other : {"r2", "r4", "hybrid"})
      EXPECT_EQ(read_all(dir / other / file), read_all(dir / "r1" / file)) << file << " differs in " << other;
  }
  // Verlet lists: ghosts are refreshed between rebuilds and the id map is reused.
  // With them, 1-2 and 1-3 pairs excluded from the pair force.
  write(dir / "v1.toml", bonds_config("[neighbor]\nmethod = \"verlet\"\nskin = 0.3\n"));
  write(dir / "v4.toml", bonds_config("[neighbor]\nmethod = \"verlet\"\nskin = 0.3\n\n" + grid_table(2, 2, 1)));
  for (const char* f : {"v1.toml", "v4.toml"}) {
    std::string text = read_all(dir / f);
    text.replace(text.find("reach = 2.0"), 11, "reach = 2.0\nexclude = \"1-3\"");
    write(dir / f, text);
  }
  ASSERT_EQ(mpirun(dir, 1, "run v1.toml --out v1").code, 0);
  const Result v4 = mpirun(dir, 4, "run v4.toml --out v4");
  ASSERT_EQ(v4.code, 0) << v4.out << v4.err;
  for (const char* file : {"checkpoint.mdpd", "thermo.csv"})
    EXPECT_EQ(read_all(dir / "v4" / file), read_all(dir / "v1" / file)) << file << " differs with Verlet lists";
  // Multiple time stepping: the inner steps refresh the ghosts' positions; same bits on 1 rank and on
  // 4 ranks x 1 or 2 threads, also after a restart from a 2-rank checkpoint.
  write(dir / "s1.toml", bonds_config(""));
  write(dir / "s2.toml", bonds_config(grid_table(2, 1, 1)));
  write(dir / "s4.toml", bonds_config(grid_table(2, 2, 1)));
  for (const char* f : {"s1.toml", "s2.toml", "s4.toml"}) {
    std::string text = read_all(dir / f);
    text.replace(text.find("reach = 2.0"), 11, "reach = 2.0\nsubcycles = 3");
    write(dir / f, text);
  }
  ASSERT_EQ(mpirun(dir, 1, "run s1.toml --out s1").code, 0);
  const Result s4 = mpirun(dir, 4, "run s4.toml --out s4");
  ASSERT_EQ(s4.code, 0) << s4.out << s4.err;
  const Result s4t = mpirun(dir, 4, "run s4.toml --out s4t", 2);
  ASSERT_EQ(s4t.code, 0) << s4t.out << s4t.err;
  ASSERT_EQ(mpirun(dir, 2, "run s2.toml --out s2half --steps 60").code, 0);
  fs::copy_file(dir / "s2half" / "checkpoint.mdpd", dir / "s60.mdpd");
  const Result s4r = mpirun(dir, 4, "run s4.toml --out s2half --restart s60.mdpd");
  ASSERT_EQ(s4r.code, 0) << s4r.out << s4r.err;
  for (const char* file : {"checkpoint.mdpd", "thermo.csv"})
    for (const char* other : {"s4", "s4t", "s2half"})
      EXPECT_TRUE(read_all(dir / other / file) == read_all(dir / "s1" / file)) << file << " differs in " << other;
  EXPECT_FALSE(read_all(dir / "s1" / "checkpoint.mdpd") == read_all(dir / "r1" / "checkpoint.mdpd"));
  // Restart: 60 steps on 2 ranks, the rest on 4, equals the uninterrupted single-rank run.
  ASSERT_EQ(mpirun(dir, 2, "run r2.toml --out a --steps 60").code, 0);
  fs::copy_file(dir / "a" / "checkpoint.mdpd", dir / "a60.mdpd");
  const Result rs = mpirun(dir, 4, "run r4.toml --out a --restart a60.mdpd");
  ASSERT_EQ(rs.code, 0) << rs.out << rs.err;
  EXPECT_EQ(read_all(dir / "a" / "checkpoint.mdpd"), read_all(dir / "r1" / "checkpoint.mdpd"));
  EXPECT_EQ(read_all(dir / "a" / "stress_profile.json"), read_all(dir / "r1" / "stress_profile.json"));
  // Momentum stays zero to round-off with bonds under decomposition.
  for (const auto& row : thermo_rows(dir / "r4" / "thermo.csv"))
    for (int k = 10; k < 13; ++k) EXPECT_LT(std::abs(row[static_cast<std::size_t>(k)]), 1e-9) << "step " << row[0];
}

// Runs the config `name` (in `dir`) on 1 rank, then on 2 and 4 ranks and 2 ranks x 2 threads, and once
// more on 2 ranks to step `half` continued on 4 ranks from that checkpoint: `files` of every run must be
// byte-identical to the 1-rank run's ("r1/...").
void expect_identical_on_ranks_and_restart(const fs::path& dir, const std::string& name,
                                           const std::vector<const char*>& files, int half) {
  ASSERT_EQ(mpirun(dir, 1, "run " + name + " --out r1").code, 0);
  for (const auto& [ranks, threads] : std::vector<std::pair<int, int>>{{2, 1}, {4, 1}, {2, 2}}) {
    const std::string out = fmt::format("r{}x{}", ranks, threads);
    const Result r = mpirun(dir, ranks, "run " + name + " --out " + out, threads);
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    for (const char* file : files)
      EXPECT_EQ(read_all(dir / out / file), read_all(dir / "r1" / file)) << file << " differs on " << out;
  }
  ASSERT_EQ(mpirun(dir, 2, fmt::format("run {} --out half --steps {}", name, half)).code, 0);
  fs::copy_file(dir / "half" / "checkpoint.mdpd", dir / "half.mdpd");
  const Result r = mpirun(dir, 4, "run " + name + " --out half --restart half.mdpd");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  for (const char* file : files)
    EXPECT_EQ(read_all(dir / "half" / file), read_all(dir / "r1" / file)) << file << " differs after a restart";
}

// Many-body DPD (a density pass whose ghost contributions go back to their owners and whose totals go
// forward to the ghosts, then the force pass): Warren's liquid with two species (different A_ij) and
// Lucy's kernel gives byte-identical checkpoints, thermo rows and trajectories on 1, 2 and 4 ranks and
// 2 ranks x 2 threads, and a run restarted from a 2-rank checkpoint on 4 ranks continues identically.
// B starts inside a ball across the periodic face x = 0 ([[species]] region): every rank creates the
// same particles while it keeps only its own.
TEST(Mpi, ManyBodyRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 303\n\n"
      "[[species]]\nname = \"A\"\ndensity = 3.0\n\n[[species]]\nname = \"B\"\ndensity = 1.5\n"
      "region = {shape = \"sphere\", center = [1.0, 4.0, 4.0], radius = 3.0}\n\n"
      "[pair]\nstyle = \"mdpd\"\na = -40.0\nb = 25.0\nrd = 0.75\ngamma = 4.5\nkernel = \"lucy\"\n\n"
      "[[pair.override]]\nspecies = [\"A\", \"B\"]\na = -30.0\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 400\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n\n"
      "[output.dump]\nevery = 100\nfields = [\"id\", \"species\", \"position\", \"velocity\", \"force\"]\n\n"
      "[analysis.droplet]\nstart = 100\nevery = 50\ninner_radius = 1.5\nouter_radius = 3.5\nblocks = 2\n";
  write(dir / "m.toml", cfg);
  expect_identical_on_ranks_and_restart(
      dir, "m.toml", {"checkpoint.mdpd", "thermo.csv", "trajectory.lammpstrj", "droplet.json", "droplet_profile.csv"}, 200);
  // The liquid is there: attraction wins over the kinetic pressure at this density.
  EXPECT_LT(thermo_rows(dir / "r1" / "thermo.csv").back()[13], 0.0);  // potential energy
}

// eDPD (pair.style = "edpd"): the temperatures travel with migrating particles and to the ghosts, and
// the ghosts' temperature rates return to their owners with the forces (4 integers per particle). A hot
// ball across the periodic face x = 0 in a cooler fluid of another heat capacity: checkpoints (with the
// temperatures) and thermo rows (with the internal energy) byte-identical on 1, 2 and 4 ranks and
// 2 ranks x 2 threads, and across a restart from 2 ranks on 4.
TEST(Mpi, EdpdRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 404\n\n"
      "[[species]]\nname = \"A\"\ndensity = 3.0\ncv = 50.0\n\n"
      "[[species]]\nname = \"H\"\ndensity = 3.0\ncv = 80.0\ntemperature = 1.4\n"
      "region = {shape = \"sphere\", center = [1.0, 4.0, 4.0], radius = 2.5}\n\n"
      "[pair]\nstyle = \"edpd\"\na = 25.0\ngamma = 4.5\nkappa = 0.02\na_t = 1.0\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n";
  write(dir / "e.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "e.toml", {"checkpoint.mdpd", "thermo.csv"}, 150);
  // Heat flowed: the hot ball's excess spread, so the mean internal temperature moved from its start
  // while the thermo file carries it (its last two columns: temp_internal, energy_internal).
  const std::vector<std::vector<double>> rows = thermo_rows(dir / "r1" / "thermo.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_GT(rows.back()[rows.back().size() - 2], 1.0);
}

// Smoothed DPD (pair.style = "sdpd"): the SPH densities go through the density pass and its ghost
// exchange, the six noise words per pair come from the pair ids (not from the rank that finds the
// pair), and the non-central force returns to the owners like any other. Two species of different
// masses, Wendland's kernel over 1.5, Tait's law with a background pressure: checkpoints and thermo
// rows byte-identical on 1, 2 and 4 ranks and 2 ranks x 2 threads, and across a restart from 2 ranks on 4.
TEST(Mpi, SdpdRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 0.5\nseed = 505\n\n"
      "[[species]]\nname = \"A\"\ndensity = 2.5\n\n[[species]]\nname = \"B\"\ndensity = 0.5\nmass = 2.0\n\n"
      "[pair]\nstyle = \"sdpd\"\nkernel = \"wendland\"\nrc = 1.5\neta = 1.0\nzeta = 0.3\nc = 6.0\nrho0 = 3.5\n"
      "eos_exponent = 7\np_b = 2.0\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n";
  write(dir / "s.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "s.toml", {"checkpoint.mdpd", "thermo.csv"}, 150);
}

// Single-particle DPD (pair.style = "spdpd"): the spins travel with migrating particles and to the
// ghosts, and the ghosts' torques return to their owners with the forces (6 integers per particle). Two
// radii and masses: checkpoints (with the spins) and thermo rows (with the rotational temperature and the
// angular momentum, summed in fixed point) byte-identical on 1, 2 and 4 ranks and 2 ranks x 2 threads,
// and across a restart from 2 ranks on 4.
TEST(Mpi, SpdpdRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 707\n\n"
      "[[species]]\nname = \"S\"\ndensity = 2.7\nradius = 0.5\n\n"
      "[[species]]\nname = \"B\"\ndensity = 0.3\nmass = 2.0\nradius = 1.0\ninertia = 0.5\n\n"
      "[pair]\nstyle = \"spdpd\"\na = 25.0\ngamma = 4.5\ngamma_perp = 3.0\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n";
  write(dir / "p.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "p.toml", {"checkpoint.mdpd", "thermo.csv"}, 150);
  // The spins carry the rotational temperature (the fourth column from the end) near kT.
  const std::vector<std::vector<double>> rows = thermo_rows(dir / "r1" / "thermo.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_NEAR(rows.back()[rows.back().size() - 4], 1.0, 0.15);
}

// Lees-Edwards shear ([lees_edwards], flow x, gradient y): the rank grid keeps x whole and splits y
// and z, so pairs across the sheared faces meet ghosts of other ranks (the image count, offset and
// image velocity come from the stored positions, as on one rank), particles migrate across the
// gradient faces with their shift and boost, and a Verlet list follows the offset's drift. Checkpoints
// and thermo rows (with the shear stress, summed in fixed point) byte-identical on 1, 2 and 4 ranks,
// 2 x 2 threads and across a restart.
TEST(Mpi, LeesEdwardsRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 606\n\n"
      "[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
      "[pair]\na = 25.0\ngamma = 4.5\n\n[neighbor]\nmethod = \"verlet\"\n\n"
      "[lees_edwards]\nshear_rate = 0.5\nstress_every = 5\n\n"
      "[integrator]\ndt = 0.02\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n";
  write(dir / "le.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "le.toml", {"checkpoint.mdpd", "thermo.csv", "shear_summary.csv"}, 150);
  // The fluid is sheared: the stress column (before the offset, the last) is positive.
  const std::vector<std::vector<double>> rows = thermo_rows(dir / "r1" / "thermo.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_GT(rows.back()[rows.back().size() - 2], 0.1);
}

// tDPD (pair.style = "tdpd") with 3 of its 4 solute channels (the partial path: 7 integers per particle
// go back from the ghosts, 3 forces and 4 channels of which the fourth stays 0), a random flux on
// solute 1 (not on solute 3, which is 0 outside the ball: a random flux would drive it negative at once,
// which stops the run), a ball rich in solute 1 across the periodic face x = 0, a [[source]] and a
// [[reaction]] in boxes that the ranks split: checkpoints and thermo rows (with the amounts
// solute1..3) byte-identical on 1, 2 and 4 ranks, 2 x 2 threads and across a restart.
TEST(Mpi, TdpdRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 505\n\n"
      "[[species]]\nname = \"A\"\ndensity = 3.0\nconc1 = 1.0\nconc2 = 2.0\n\n"
      "[[species]]\nname = \"R\"\ndensity = 3.0\nconc1 = 5.0\nconc3 = 1.0\n"
      "region = {shape = \"sphere\", center = [1.0, 4.0, 4.0], radius = 2.5}\n\n"
      "[pair]\nstyle = \"tdpd\"\na = 25.0\ngamma = 4.5\nrcc = 1.2\nkappa1 = 2.0\nkappa2 = 1.0\nkappa3 = 4.0\n"
      "epsilon1 = 0.02\n\n[tdpd]\nsolutes = 3\n\n"
      "[[source]]\nfield = \"conc2\"\nrate = 0.3\nlo = [2.0, 0.0, 0.0]\nhi = [6.0, 8.0, 4.0]\n\n"
      "[[reaction]]\nsolute = 1\nproduct = 3\nrate = 0.5\nlo = [0.0, 3.0, 0.0]\nhi = [8.0, 8.0, 8.0]\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n";
  write(dir / "t.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "t.toml", {"checkpoint.mdpd", "thermo.csv"}, 150);
  // Solute moved: the reaction turned some of solute 1 into solute 3 (the last three columns are the
  // amounts of solutes 1-3).
  const std::vector<std::vector<double>> rows = thermo_rows(dir / "r1" / "thermo.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_LT(rows.back()[rows.back().size() - 3], rows.front()[rows.front().size() - 3]);
  EXPECT_GT(rows.back()[rows.back().size() - 1], rows.front()[rows.front().size() - 1]);
}

// [analysis.flux] (analysis/scalar_flux.hpp): eDPD between walls held at 1.1 (z < 1) and 0.9 (z > 9),
// the walls' heat summed over ranks at every step, the planes' pair part from the gathered system:
// flux.json, flux.csv and flux_profile.csv byte-identical on 1, 2 and 4 ranks, 2 x 2 threads and across
// a restart in the middle of a sampling interval.
TEST(Mpi, HeatFluxAnalysisIsBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 8.0, 10.0]\nperiodic = [true, true, false]\nkT = 1.0\nseed = 606\n\n"
      "[[species]]\nname = \"fluid\"\ndensity = 3.0\ncv = 100.0\n\n"
      "[[species]]\nname = \"hot\"\nfrozen = true\ncv = 100.0\ntemperature = 1.1\n\n"
      "[[species]]\nname = \"cold\"\nfrozen = true\ncv = 100.0\ntemperature = 0.9\n\n"
      "[pair]\nstyle = \"edpd\"\na = 25.0\ngamma = 4.5\nkappa = 0.1\n\n"
      "[[solid]]\nname = \"b\"\nspecies = \"hot\"\nshape = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 0, 1]\n\n"
      "[[solid]]\nname = \"t\"\nspecies = \"cold\"\nshape = \"plane\"\npoint = [0, 0, 9]\nnormal = [0, 0, -1]\n\n"
      "[integrator]\ndt = 0.01\n\n[run]\nsteps = 300\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n\n"
      "[analysis.flux]\naxis = \"z\"\nposition = 3.0\nplanes = 3\nspacing = 2.0\nstart = 20\nevery = 7\nblocks = 4\n";
  write(dir / "f.toml", cfg);
  expect_identical_on_ranks_and_restart(dir, "f.toml", {"checkpoint.mdpd", "flux.json", "flux.csv", "flux_profile.csv"},
                                        151);
  EXPECT_NE(read_all(dir / "r1" / "flux.json").find("\"walls\""), std::string::npos);  // the files were written
}

// Verlet lists (ghost refresh between rebuilds), two species, a body force, reverse Poiseuille flow, RDF,
// MSD and a GSD trajectory: every output file is the same on 3 ranks (automatic grid) as on one.
TEST(Mpi, EveryFeatureWorksUnderDecomposition) {
  const fs::path dir = fresh_dir();
  const std::string cfg =
      "[system]\nbox = [8.0, 7.0, 9.0]\nkT = 1.0\nseed = 11\n\n"
      "[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
      "[[species]]\nname = \"B\"\ncount = 300\nbody_force = [0.01, 0.0, 0.0]\n\n"
      "[pair]\na = 25.0\ngamma = 4.5\n\n[integrator]\ndt = 0.04\n\n[run]\nsteps = 600\n\n"
      "[neighbor]\nmethod = \"verlet\"\nskin = 0.8\n\n"
      "[output]\nthermo_every = 50\nprogress = false\n\n"
      "[output.dump]\nformat = \"gsd\"\nevery = 200\nfields = [\"id\", \"species\", \"position\", \"velocity\", "
      "\"force\", \"image\"]\n\n"
      "[poiseuille]\nforce = 0.02\nstart = 100\nevery = 5\nblocks = 4\n\n"
      "[analysis.rdf]\nevery = 100\n\n[analysis.msd]\nevery = 100\n\n"
      "[[analysis.fields]]\nname = \"map\"\nbins = [8, 1, 9]\nevery = 5\nexclude = [\"B\"]\n\n"
      "[[analysis.fields]]\nname = \"part\"\nbins = [3, 7, 2]\nlo = [1.5, 0, 2]\nhi = [7.5, 7, 8]\nevery = 20\n";
  write(dir / "f.toml", cfg);
  ASSERT_EQ(mpirun(dir, 1, "run f.toml --out one").code, 0);
  const Result r = mpirun(dir, 3, "run f.toml --out three");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  for (const char* file : {"checkpoint.mdpd", "thermo.csv", "trajectory.gsd", "poiseuille_profile.csv", "rdf.csv",
                           "msd.csv", "viscosity.json", "map.vti", "map.csv", "part.vti", "part.csv"})
    EXPECT_EQ(read_all(dir / "three" / file), read_all(dir / "one" / file)) << file;
  // The Verlet list really was reused between rebuilds (so ghosts were refreshed, not rebuilt).
  const auto rows = thermo_rows(dir / "three" / "thermo.csv");
  EXPECT_LT(rows.back()[16], 0.5 * rows.back()[0]) << "neighbor_builds";
}

TEST(Mpi, RefusesADecompositionThinnerThanTheGhostWidth) {
  const fs::path dir = fresh_dir();
  // Verlet cells are at least 1.3 wide: 6 cells along x cannot give 8 ranks one cell each.
  write(dir / "thin.toml",
        fluid_config("[neighbor]\nmethod = \"verlet\"\nskin = 0.3\n\n" + grid_table(8, 1, 1) + kOutput));
  const Result r = mpirun(dir, 8, "run thin.toml --out out");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("parallel.grid"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("thinner than the ghost width"), std::string::npos) << r.err;
  write(dir / "count.toml", fluid_config(grid_table(2, 2, 1) + kOutput));
  const Result c = mpirun(dir, 2, "run count.toml --out out");
  EXPECT_EQ(c.code, 2);
  EXPECT_NE(c.err.find("needs 4 ranks but the run has 2"), std::string::npos) << c.err;
}

// The pairwise thermostats under MPI: rank 0 gathers the particles, sweeps the whole system in the
// one-rank order and broadcasts the velocities back by id. Stoyanov-Groot (Lowe-Andersen collisions
// and the kick steered by the whole system's temperature across the flow) under Lees-Edwards shear:
// checkpoints, thermo rows and the shear stress (which holds the sweep's virial) byte-identical on 1, 2
// and 4 ranks and 2 x 2 threads, and after a restart from 2 ranks onto 4. (The other three types share
// the gather and the sweep; they differ in the pair update only.)
TEST(Mpi, PairThermostatRunsAreBitIdenticalOnOneTwoAndFourRanksAndAcrossARestart) {
  const fs::path dir = fresh_dir();
  write(dir / "t.toml",
        "[system]\nbox = [8.0, 8.0, 8.0]\nkT = 1.0\nseed = 707\n\n"
        "[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
        "[pair]\na = 25.0\ngamma = 0.0\n\n[integrator]\ndt = 0.02\n\n[run]\nsteps = 120\n\n"
        "[output]\nthermo_every = 30\nprogress = false\n\n"
        "[thermostat]\ntype = \"stoyanov-groot\"\nrate = 5.0\nalpha = 4.5\n\n"
        "[lees_edwards]\nshear_rate = 0.5\nstress_every = 5\n");
  const std::vector<const char*> files{"checkpoint.mdpd", "thermo.csv", "shear_summary.csv"};
  expect_identical_on_ranks_and_restart(dir, "t.toml", files, 60);
  for (const char* file : files) EXPECT_FALSE(read_all(dir / "r1" / file).empty()) << file;
}

// A blow-up on a decomposed run stops every rank with the same step and particle as on one rank.
TEST(Mpi, BlowUpIsReportedLikeOnOneRank) {
  const fs::path dir = fresh_dir();
  // An unstable time step: a = 25 with dt = 0.5 explodes within about ten steps.
  std::string cfg = fluid_config("[output]\nprogress = false\n");
  cfg.replace(cfg.find("dt = 0.04"), 9, "dt = 0.5");
  write(dir / "b.toml", cfg);
  const Result one = mpirun(dir, 1, "run b.toml --out one");
  const Result four = mpirun(dir, 4, "run b.toml --out four");
  EXPECT_EQ(one.code, 3) << one.err;
  EXPECT_EQ(four.code, 3) << four.err;
  const auto message = [](const std::string& err) {
    const auto at = err.find("blew up at step");
    return at == std::string::npos ? std::string() : err.substr(at, err.find('\n', at) - at);
  };
  EXPECT_FALSE(message(one.err).empty()) << one.err;
  EXPECT_EQ(message(four.err), message(one.err));
}

// A rank that starts with no particles (the fluid fills the lower half of x only, and the upper half is
// another rank's domain) takes part in every collective step: it used to skip the return of ghost
// forces while the other rank waited for it, and the run hung. Now it runs, bit-identical to one rank,
// and particles that diffuse into the empty domain are handed over.
TEST(Mpi, ARankThatStartsEmptyTakesPartAndGivesTheSameBits) {
  const fs::path dir = fresh_dir();
  std::string one = fluid_config("[output]\nthermo_every = 20\nprogress = false\n");
  one.replace(one.find("density = 3.0"), 13,
              "density = 3.0\nregion = { shape = \"box\", lo = [0.0, 0.0, 0.0], hi = [4.0, 8.0, 8.0] }");
  one.replace(one.find("steps = 2000"), 12, "steps = 100");
  write(dir / "one.toml", one);
  write(dir / "two.toml", one + grid_table(2, 1, 1));
  const Result r1 = mpirun(dir, 1, "run one.toml --out one");
  ASSERT_EQ(r1.code, 0) << r1.err;
  const Result r2 = mpirun(dir, 2, "run two.toml --out two");
  ASSERT_EQ(r2.code, 0) << r2.out << r2.err;
  EXPECT_EQ(read_all(dir / "two" / "thermo.csv"), read_all(dir / "one" / "thermo.csv"));
  EXPECT_EQ(read_all(dir / "two" / "checkpoint.mdpd"), read_all(dir / "one" / "checkpoint.mdpd"));
}

}  // namespace

TEST(Mpi, DensityPassIsBruteForceAndRankIndependent) {
  // Multi-pass pair computations: the local density with Warren's kernel equals a brute-force sum
  // exactly, ghosts receive their owners' values, and the result is bit-identical on 1, 2 and 4 ranks
  // and 1 and 2 threads (two species, after 30 steps so particles have crossed domain boundaries).
  const fs::path dir = fresh_dir();
  {
    std::ofstream cfg(dir / "fluid.toml");
    cfg << "[system]\nbox = [9.0, 9.0, 9.0]\nkT = 1.0\nseed = 7\n\n"
           "[[species]]\nname = \"A\"\ndensity = 2.0\n\n[[species]]\nname = \"B\"\ndensity = 1.0\n\n"
           "[pair]\na = 25.0\ngamma = 4.5\n\n[integrator]\ndt = 0.04\n\n[run]\nsteps = 30\n";
  }
  std::string first;
  for (const auto& [ranks, threads] : std::vector<std::pair<int, int>>{{1, 1}, {2, 1}, {4, 1}, {1, 2}, {2, 2}}) {
    const std::string out = fmt::format("rho_{}x{}.txt", ranks, threads);
    const Result r = mpirun(dir, ranks, "fluid.toml 30 " + out, threads, MESODPD_DENSITY_PROBE);
    ASSERT_EQ(r.code, 0) << ranks << " ranks x " << threads << " threads\n" << r.out << r.err;
    EXPECT_NE(r.out.find(" 0 failures"), std::string::npos) << r.out;
    if (ranks > 1) {
      EXPECT_EQ(r.out.find(" 0 ghosts"), std::string::npos) << "no ghosts were checked: " << r.out;
    }
    const std::string text = read_all(dir / out);
    EXPECT_GT(text.size(), 2187u * 10);  // 2,187 particles
    if (first.empty()) {
      first = text;
    } else {
      EXPECT_EQ(text, first) << ranks << " ranks x " << threads << " threads differ from 1 rank";
    }
  }
}

// Bounded axes under decomposition: no ghost exchange or migration across a bounded face, and the same
// cell pairs as one rank. Step-0 forces and the state after 5 steps (positions, velocities, forces in id
// order) must be byte-identical on 1, 2 and 4 ranks, with the bounded axis split. With bounded axes the
// decomposition sends fewer ghosts than the periodic box on the same grid (none across the faces).
TEST(Mpi, BoundedAxesGiveTheSameBitsOnOneTwoAndFourRanks) {
  const fs::path dir = fresh_dir();
  struct Case {
    std::string name, periodic, box;
    std::vector<std::string> grids;  // the first is one rank
  };
  const std::vector<Case> cases = {
      {"z", "ttf", "6 6 6", {"1 1 1", "1 1 2", "1 2 2", "1 1 4"}},
      {"xz", "ftf", "6 6 6", {"1 1 1", "2 1 1", "2 1 2"}},
      // Two cells along the bounded axis: allowed under MPI (no wrap), one cell per rank.
      {"thin", "ttf", "6 6 2.5", {"1 1 1", "1 1 2", "2 1 2"}},
  };
  for (const Case& c : cases) {
    std::string reference;
    for (const std::string& grid : c.grids) {
      const int ranks = [&] {
        int a = 0, b = 0, e = 0;
        std::sscanf(grid.c_str(), "%d %d %d", &a, &b, &e);
        return a * b * e;
      }();
      const std::string file = c.name + "_" + std::to_string(ranks) + ".bin";
      const Result r = mpirun(dir, ranks, file + " " + c.periodic + " " + c.box + " " + grid + " 5", 1,
                              MESODPD_BOUNDED_RUN);
      ASSERT_EQ(r.code, 0) << c.name << " on " << ranks << " ranks: " << r.err;
      EXPECT_NE(r.out.find("grid " + grid), std::string::npos) << r.out;
      const std::string bits = read_all(dir / file);
      ASSERT_GT(bits.size(), 1000u);
      if (ranks == 1) {
        EXPECT_NE(r.out.find("ghosts 0"), std::string::npos) << r.out;
        reference = bits;
      } else {
        EXPECT_EQ(bits, reference) << c.name << ": " << ranks << " ranks (grid " << grid << ") differ from one rank";
      }
    }
  }
  // Ghost counts: 2 ranks along a periodic z exchange both faces of their slabs; along a bounded z only
  // the face they share.
  auto ghosts = [&](const std::string& periodic) {
    const Result r = mpirun(dir, 2, "g.bin " + periodic + " 6 6 6 1 1 2 0", 1, MESODPD_BOUNDED_RUN);
    EXPECT_EQ(r.code, 0) << r.err;
    const auto at = r.out.find("ghosts ");
    return at == std::string::npos ? 0L : std::atol(r.out.c_str() + at + 7);
  };
  const long periodic = ghosts("ttt"), bounded = ghosts("ttf");
  EXPECT_GT(bounded, 0);
  EXPECT_LT(bounded, periodic);
}

// Frozen-particle walls under decomposition: a channel bounded along z with a pillar, Maxwellian
// reflections (the counter-based wall noise) and a body force. Frozen particles are owned, migrated and
// ghosted like any other, the pair loop skips frozen-frozen pairs on every rank alike, and reflections
// and drag sums act per particle or in integers, and the adaptive near-wall force's bin counts are
// integers summed over ranks, and the fluid the walls are cut from is equilibrated first (a run of its
// own, gathered by id): thermo.csv (with the reflection and penetration counts), drag.csv,
// adaptive.csv and the checkpoint are byte-identical on 1, 2 and 4 ranks and 1 and 2 threads.
TEST(Mpi, WallsGiveTheSameBitsOnOneTwoFourRanksAndTwoThreads) {
  const fs::path dir = fresh_dir();
  write(dir / "walls.toml",
        "[system]\nbox = [9.0, 6.0, 9.0]\nperiodic = [true, true, false]\nkT = 1.0\nseed = 99\n\n"
        "[[species]]\nname = \"fluid\"\ndensity = 3.0\nbody_force = [0.05, 0, 0]\n\n"
        "[[species]]\nname = \"wall\"\nfrozen = true\n\n"
        "[pair]\na = 25.0\ngamma = 4.5\n\n[integrator]\ndt = 0.04\n\n[run]\nsteps = 150\n\n"
        "[[solid]]\nname = \"bottom\"\nspecies = \"wall\"\nshape = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 0, 1]\n\n"
        "[[solid]]\nname = \"top\"\nspecies = \"wall\"\nshape = \"plane\"\npoint = [0, 0, 8]\nnormal = [0, 0, -1]\n"
        "velocity = [0.2, 0, 0]\n\n"
        "[[solid]]\nname = \"pillar\"\nspecies = \"wall\"\nshape = \"cylinder\"\ncenter = [4.5, 3, 4.5]\n"
        "direction = [0, 1, 0]\nradius = 1.5\n\n"
        "[walls]\nreflection = \"maxwell\"\ndrag_every = 5\nadaptive = true\nadaptive_every = 10\nequilibrate = 20\n\n"
        "[output]\nthermo_every = 10\nprogress = false\n");
  std::string thermo, drag, checkpoint, adaptive;
  for (const auto& [ranks, threads] : std::vector<std::pair<int, int>>{{1, 1}, {2, 1}, {4, 1}, {1, 2}, {2, 2}}) {
    const std::string out = fmt::format("out_{}x{}", ranks, threads);
    const Result r = mpirun(dir, ranks, "run walls.toml --out " + out, threads);
    ASSERT_EQ(r.code, 0) << ranks << " ranks x " << threads << " threads\n" << r.out << r.err;
    const std::string t = read_all(dir / out / "thermo.csv"), d = read_all(dir / out / "drag.csv"),
                      c = read_all(dir / out / "checkpoint.mdpd"), a = read_all(dir / out / "adaptive.csv");
    ASSERT_NE(t.find("reflections,penetrations"), std::string::npos) << t;
    ASSERT_GT(d.size(), 1000u);
    ASSERT_GT(a.size(), 1000u);
    if (thermo.empty()) {
      thermo = t, drag = d, checkpoint = c, adaptive = a;
      continue;
    }
    EXPECT_EQ(a, adaptive) << ranks << " ranks x " << threads << " threads: adaptive.csv differs";
    EXPECT_EQ(t, thermo) << ranks << " ranks x " << threads << " threads: thermo.csv differs";
    EXPECT_EQ(d, drag) << ranks << " ranks x " << threads << " threads: drag.csv differs";
    EXPECT_EQ(c, checkpoint) << ranks << " ranks x " << threads << " threads: checkpoint differs";
  }
}
