// Running gnuplot (Debian gnuplot-nox) on a script and taking its picture:
// a PNG file renamed into place, or an SVG document to inline in HTML.
// gnuplot is optional: its absence is a warning, never an error.
#ifndef COMMON_GNUPLOT_H_
#define COMMON_GNUPLOT_H_

#include <functional>
#include <string>

namespace axis {

// The path of the executable `name` in the first directory of $PATH that
// has one (a regular file with execute permission), or "" if none.
std::string FindExecutable(const std::string& name);

// Runs gnuplot on script(temporary_png_path) and renames the image to
// png_path. Returns false with *warning set ("gnuplot not found: no plot
// written for <what>", or gnuplot's failure) instead of throwing; throws
// std::runtime_error only if the finished image cannot be renamed.
bool RenderGnuplotPng(const std::string& png_path,
                      const std::function<std::string(const std::string&)>& script,
                      const std::string& what, std::string* warning);

// Runs gnuplot on script(temporary_svg_path) (the script sets gnuplot's
// `svg` terminal, best with `dynamic` so that the picture scales, and never
// `mouse`, which loads a script) in `scratch_dir` and returns in *svg the
// picture ready to be inlined into an HTML page (report/html_report.h): the
// XML prolog and DOCTYPE dropped, the namespace declarations removed
// (implied in HTML), xlink:href written href, every id and every reference
// to one (href="#…", url(#…)) prefixed with `id_prefix` so that several
// plots can share a page. The temporary file is removed. Returns false
// with *warning set (gnuplot missing or failing, as RenderGnuplotPng; or
// the SVG refers to anything outside itself: http:, https:, a script, an
// image, @import, src=) and *svg empty; never throws.
bool RenderGnuplotSvg(const std::string& scratch_dir,
                      const std::function<std::string(const std::string&)>& script,
                      const std::string& what, const std::string& id_prefix,
                      std::string* svg, std::string* warning);

// Whether `s` holds a line break (a path gnuplot's -e cannot take). Never
// throws.
bool HasLineBreak(const std::string& s);

}  // namespace axis

#endif  // COMMON_GNUPLOT_H_
