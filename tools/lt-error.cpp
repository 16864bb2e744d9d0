// lt-error: the error of renders against a reference, for every snapshot a buffer file holds, so one run
// gives a whole error-against-time curve; as a table, CSV, JSON, a log-log plot and a per-pixel map.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common/info.h"
#include "common/tool.h"
#include "image/buffer_source.h"
#include "image/error_metrics.h"
#include "image/image_io.h"
#include "util/temp_output.h"

extern char** environ;

namespace {

// Debian's interpreter, which has python3-matplotlib; the python3 first on PATH may be another one
// (a virtualenv, conda) without it.
constexpr const char* kPython = "/usr/bin/python3";

// Error against wall time on log-log axes, one line with markers per input, a dashed line of slope -1
// (the 1/t convergence of an unbiased Monte Carlo estimator whose cost grows linearly with time) through
// the first input's first point. argv: CSV (lt-error's columns), PNG to write, metric name.
constexpr const char* kPlotScript = R"PY(
import csv, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

csv_path, png_path, metric = sys.argv[1:4]
curves = {}
with open(csv_path, newline="") as f:
    for row in csv.DictReader(f):
        if not row["time"] or not row["error"]:
            continue
        t, e = float(row["time"]), float(row["error"])
        if t > 0 and e > 0:
            curves.setdefault(row["input"], []).append((t, e))
if not curves:
    sys.exit("no row with a positive time and error to plot")
names = list(curves)
short = [os.path.basename(n) for n in names]
labels = short if len(set(short)) == len(short) else names
fig, ax = plt.subplots(figsize=(6, 4.5), dpi=150)
for name, label in zip(names, labels):
    points = sorted(curves[name])
    ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", markersize=4, label=label)
t0, e0 = curves[names[0]][0]
times = [p[0] for c in curves.values() for p in c]
lo, hi = min(times), max(times)
if hi <= lo:
    lo, hi = lo / 2, hi * 2
ax.plot([lo, hi], [e0 * t0 / lo, e0 * t0 / hi], linestyle="--", color="gray", linewidth=1, label="slope -1")
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("wall time [s]")
ax.set_ylabel(metric)
ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
ax.legend()
fig.tight_layout()
fig.savefig(png_path, format="png")
)PY";

// A file written under a temporary name and renamed when complete (TempOutput), through a stream.
template <typename Write> void writeText(const std::string& path, Write write) {
    lt::TempOutput temp(path);
    {
        std::ofstream out(temp.path(), std::ios::binary);
        if (!out) throw lt::Error(path + ": cannot create (" + std::strerror(errno) + ")");
        write(out);
        out.flush();
        if (!out) throw lt::Error(path + ": write failed (" + std::strerror(errno) + ")");
    }
    temp.commit();
}

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s)
        q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

// Numbers with all the digits a double needs (CSV, plots), or empty when unknown.
std::string exact(std::optional<double> v) {
    if (!v) return "";
    std::ostringstream s;
    s.precision(17);
    s << *v;
    return s.str();
}
std::string exact(std::optional<uint64_t> v) { return v ? std::to_string(*v) : ""; }

void writeCsv(std::ostream& out, const std::vector<lt::ErrorCurve>& curves, const std::string& metric) {
    out << "input,label,time,cpu_time,samples,metric,error,efficiency,scale,error_rescaled\n";
    for (const auto& c : curves)
        for (const auto& r : c.rows)
            out << csvField(c.name) << ',' << csvField(r.label) << ',' << exact(r.wallSeconds) << ','
                << exact(r.cpuSeconds) << ',' << exact(r.samples) << ',' << metric << ','
                << exact(std::optional(r.error.value)) << ',' << exact(r.efficiency()) << ','
                << exact(std::optional(r.scale)) << ',' << exact(std::optional(r.rescaledError.value)) << '\n';
}

nlohmann::json toJson(const std::vector<lt::ErrorCurve>& curves, const std::string& metric, const std::string& ref,
                      const lt::ErrorOptions& options) {
    const auto opt = [](const auto& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    nlohmann::json j{{"metric", metric}, {"reference", ref}, {"trim", options.trim}, {"crop", nullptr}};
    if (options.crop) j["crop"] = {options.crop->x, options.crop->y, options.crop->width, options.crop->height};
    j["rows"] = nlohmann::json::array();
    for (const auto& c : curves)
        for (const auto& r : c.rows)
            j["rows"].push_back({{"input", c.name},
                                 {"label", r.label},
                                 {"time", opt(r.wallSeconds)},
                                 {"cpu_time", opt(r.cpuSeconds)},
                                 {"samples", opt(r.samples)},
                                 {"error", r.error.value},
                                 {"efficiency", opt(r.efficiency())},
                                 {"scale", std::isfinite(r.scale) ? nlohmann::json(r.scale) : nlohmann::json(nullptr)},
                                 {"error_rescaled", r.rescaledError.value},
                                 {"pixels", r.error.pixels},
                                 {"trimmed", r.error.trimmed}});
    return j;
}

std::string shortNumber(std::optional<double> v, const char* format) {
    if (!v) return "-";
    char text[64];
    std::snprintf(text, sizeof text, format, *v);
    return text;
}

void printTable(std::ostream& out, const std::vector<lt::ErrorCurve>& curves, const std::string& metric) {
    std::vector<std::vector<std::string>> cells{
        {"input", "image", "time [s]", "samples", metric, "efficiency", "scale", metric + " rescaled"}};
    for (const auto& c : curves)
        for (const auto& r : c.rows)
            cells.push_back({c.name, r.label, shortNumber(r.wallSeconds, "%.4g"),
                             r.samples ? std::to_string(*r.samples) : "-",
                             shortNumber(std::optional(r.error.value), "%.5g"), shortNumber(r.efficiency(), "%.5g"),
                             shortNumber(std::optional(r.scale), "%.4f"),
                             shortNumber(std::optional(r.rescaledError.value), "%.5g")});
    std::vector<size_t> width(cells[0].size(), 0);
    for (const auto& row : cells)
        for (size_t i = 0; i < row.size(); ++i)
            width[i] = std::max(width[i], row[i].size());
    for (const auto& row : cells) {
        std::string line;
        for (size_t i = 0; i < row.size(); ++i) {
            // Names left-aligned, numbers right-aligned so their digits line up.
            const std::string pad(width[i] - row[i].size(), ' ');
            line += (i < 2 ? row[i] + pad : pad + row[i]) + (i + 1 < row.size() ? "  " : "");
        }
        out << line << '\n';
    }
}

// Runs the plot script with Debian's python; its stderr is kept so a failure becomes one error line.
void plot(const std::string& csvPath, const std::string& pngPath, const std::string& metric) {
    if (::access(kPython, X_OK) != 0)
        throw lt::Error(pngPath + ": --plot needs " + kPython + " with matplotlib (Debian: python3-matplotlib)");
    int pipeFds[2];
    if (::pipe(pipeFds) != 0) throw lt::Error(std::string("cannot create a pipe: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDERR_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
    posix_spawn_file_actions_addclose(&actions, pipeFds[1]);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    // -I: isolated mode, so PYTHONPATH or user site packages meant for another interpreter cannot break it.
    std::vector<std::string> args{kPython, "-I", "-c", kPlotScript, csvPath, pngPath, metric};
    std::vector<char*> argv;
    for (auto& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, kPython, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeFds[1]);
    std::string messages;
    char chunk[4096];
    for (ssize_t n; (n = ::read(pipeFds[0], chunk, sizeof chunk)) != 0;) {
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) break;
        messages.append(chunk, size_t(n));
    }
    ::close(pipeFds[0]);
    if (spawned != 0) throw lt::Error(pngPath + ": cannot run " + kPython + " (" + std::strerror(spawned) + ")");
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        // The last line of a traceback says what went wrong.
        std::string last;
        std::istringstream lines(messages);
        for (std::string line; std::getline(lines, line);)
            if (!line.empty()) last = line;
        throw lt::Error(pngPath + ": plotting failed" + (last.empty() ? "" : ": " + last));
    }
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"lt-error: the error of renders against a reference. Every snapshot of a buffer file is measured, "
                 "then its final buffer, so one run gives an error-against-time curve; EXR inputs give one row "
                 "without a time. Efficiency is 1 / (error x wall time). Scale is the factor that brings the image's "
                 "mean (over the crop) to the reference's, and the rescaled error is the error of the image times that "
                 "factor: what is left once the scale is right (a Markov chain's normalization b shows as scale).",
                 "lt-error"};
    std::vector<std::string> inputs;
    std::string refPath, metricName = "relmse", cropText, csvOut, plotOut, mapOut;
    double trim = 0;
    bool json = false;
    app.add_option("IN", inputs, "buffer files (.lts, - for stdin) or EXR images")->required();
    app.add_option("--ref", refPath, "reference: an EXR or a buffer file (its final image)")->required();
    app.add_option("--metric", metricName,
                   "relmse (default; [GDPR]: per pixel sum_c (I-ref)^2 / (mean_c(ref)^2 + 0.001)), rrmse (its "
                   "square root), mse, mape (|I-ref| / (|ref| + 0.01)), smape (2|I-ref| / (|I|+|ref|))")
        ->check(CLI::IsMember({"relmse", "rrmse", "mse", "mape", "smape"}));
    app.add_option("--trim", trim, "drop this fraction of the pixels with the largest error (default 0)")
        ->check(CLI::Range(0.0, 0.999999));
    app.add_option("--crop", cropText, "measure only the pixels X,Y,W,H (default: the whole image)");
    app.add_option("--csv", csvOut, "write the rows as CSV");
    app.add_flag("--json", json, "print the rows as JSON instead of the table");
    app.add_option("--plot", plotOut, "draw error against time on log-log axes into this PNG (needs matplotlib)");
    app.add_option("--map", mapOut, "write the per-pixel error of the first input's final image (channel \"error\")");
    return lt::tool::run(app, argc, argv, [&] {
        lt::ErrorOptions options;
        options.metric = lt::parseErrorMetric(metricName);
        options.trim = trim;
        if (!cropText.empty()) options.crop = lt::parseCrop(cropText);
        const std::string metric = lt::errorMetricName(options.metric);

        lt::BufferSource refSource = lt::loadBuffer(refPath);
        const lt::ErrorReference reference(std::move(refSource.buffer), refSource.name);
        std::vector<lt::ErrorCurve> curves;
        for (const auto& in : inputs)
            curves.push_back(lt::measureErrorCurve(in, reference, options));

        if (!csvOut.empty()) writeText(csvOut, [&](std::ostream& out) { writeCsv(out, curves, metric); });
        if (!plotOut.empty()) {
            bool anyTime = false;
            for (const auto& c : curves)
                for (const auto& r : c.rows)
                    anyTime = anyTime || r.wallSeconds.has_value();
            if (!anyTime) throw lt::Error(plotOut + ": nothing to plot: no input has a time (EXR images carry none)");
            // The script reads the rows as CSV; this temporary one is never committed, so it is removed.
            lt::TempOutput rows(plotOut + ".csv");
            writeText(rows.path(), [&](std::ostream& out) { writeCsv(out, curves, metric); });
            lt::TempOutput png(plotOut);
            plot(rows.path(), png.path(), metric);
            png.commit();
        }
        if (!mapOut.empty()) {
            const auto& first = curves.front();
            lt::file::Buffer map;
            map.width = first.width;
            map.height = first.height;
            map.channels = {"error"};
            map.planes.emplace_back(first.finalErrors.begin(), first.finalErrors.end());
            nlohmann::json info = lt::tool::makeInfo("lt-error", argc, argv, {{"metric", metric}}, nullptr);
            info["input"] = first.name;
            info["reference"] = reference.name();
            lt::writeExr(mapOut, map, info);
        }

        if (json) {
            std::cout << toJson(curves, metric, reference.name(), options).dump(2) << '\n';
        } else {
            printTable(std::cout, curves, metric);
            const lt::ImageError& e = curves.front().rows.front().error;
            if (options.crop) std::cout << "crop " << cropText << ": " << e.pixels + e.trimmed << " pixels per image\n";
            if (options.trim > 0)
                std::cout << "trimmed " << e.trimmed << " of " << e.pixels + e.trimmed << " pixels per image (the "
                          << options.trim * 100 << "% with the largest " << metric << ")\n";
        }
        return 0;
    });
}
