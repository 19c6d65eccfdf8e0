//! The case the stability tests share: the case-3 demo case file and its track.

/// The case-3 demo case and the beam model's track of it.
pub fn case3_track() -> (
    squeal::model::case::LoadedCase,
    squeal::stability::rail::Track,
) {
    let loaded =
        squeal::model::case::load_case(std::path::Path::new("data/cases/case3-demo.json")).unwrap();
    let track = squeal::stability::rail::Track::from_case(&loaded).unwrap();
    (loaded, track)
}
