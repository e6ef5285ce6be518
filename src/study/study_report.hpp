#pragma once
// What a study writes: study.json (everything), study.csv (one row per quantity and level, cost beside
// error), levels.csv (cost per level, predicted and actual), series/*.csv (each series of every level on the
// common time base, with the extrapolated series), report.md, and the plots made by
// pipelines/study/plot_study.py when a Python with matplotlib is found (docs/study.md).
#include <string>

#include "study/study.hpp"

namespace varsph::study {

void write_study_outputs(const StudyResult& r);  // study.json, study.csv, levels.csv, series/, report.md
void write_report(const StudyResult& r);         // report.md only
std::string make_plots(const StudyResult& r);    // runs the plot script; says what happened
void print_summary(const StudyResult& r);

}  // namespace varsph::study
