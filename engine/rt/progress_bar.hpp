#pragma once
// The ray tracer's progress bar on stderr (Options::progress): filled share, samples, time, ETA.
namespace candela::rt {

// Redraws the bar in place; the last call (done == total) ends the line.
void progress_bar(int done, int total, double elapsed_s);

}  // namespace candela::rt
