//! fringe's integration tests, one binary (one link instead of one per file): each module is
//! one former `tests/<name>.rs`. Shared strategies and independent reference helpers live in
//! `common`, shared scenes and the library listing in `support`. Data files stay in `tests/data`
//! and `tests/bad_cases`.

mod common;
mod support;

mod accumulate;
mod airy_tail;
mod beats;
mod beyond_critical;
mod case_library;
mod case_parser_props;
mod case_runs;
mod cli;
mod closed_form_precision;
mod colour;
mod energy;
mod fast_paths;
mod figures;
mod forward;
mod fresnel_pinned;
mod fresnel_props;
mod fuzz;
mod fuzz_generators;
mod golden_reproducibility;
mod grade;
mod input_classes;
mod interaction_props;
mod invariance;
mod layers;
mod material;
mod output_safety;
mod path_solver;
mod pipeline_props;
mod precision_classes;
mod render;
mod renderer_models;
mod round_trips;
mod scalar_tail;
mod spectrum_batch;
mod stability;
mod stability_report;
mod stack_kernel;
mod tradeoff;
mod trail;
mod truth;
mod truth_airy_tracer;
mod truth_beyond_critical_plates;
mod truth_carried_invariant;
mod truth_found_edges;
mod truth_geometry;
mod truth_grazing;
mod truth_grazing_brewster;
mod truth_grazing_plane_waves;
mod truth_plate_landing;
mod truth_plates;
mod truth_point_sources;
mod truth_refusals;
mod truth_representation;
mod truth_small_deviations;
mod truth_tail_closure;
mod truth_thick_plates;
mod truth_tunnelling;
mod unit;
mod unpolarized;
mod young_two_point;
