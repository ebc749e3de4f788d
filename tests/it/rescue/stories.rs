//! Each story's volume loss (`src/rescue/stories.rs`, docs/rescue.md §2).
use super::scene::*;
use fem2rbd::rescue::{analyse, Ruin, Sizes};

/// A pancaked first story loses all the free space under its ceiling, the standing second
/// story none: before 11.28 m³ each (exact on the aligned 0.1 m grid), after 0 and 11.28.
#[test]
fn a_pancaked_story_loses_its_volume_and_a_standing_one_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &two_stories_first_pancaked(), &[], 1.0);
    let a = analyse(&Ruin::load(dir.path()).unwrap(), Sizes::default()).unwrap();
    assert_eq!(a.stories.len(), 2);
    let (s1, s2) = (&a.stories[0], &a.stories[1]);
    assert_eq!((s1.story, s2.story), (1, 2));
    assert_eq!((s1.ceiling_z_m, s2.ceiling_z_m), (2.1, 4.3));
    assert!((s1.before_m3 - 11.28).abs() < 1e-9, "{s1:?}");
    assert!((s2.before_m3 - 11.28).abs() < 1e-9, "{s2:?}");
    assert_eq!(s1.after_m3, 0.0);
    assert_eq!(s1.loss, 1.0);
    assert!((s2.after_m3 - 11.28).abs() < 1e-9, "{s2:?}");
    assert!(s2.loss.abs() < 1e-12, "{s2:?}");
    let js = a.json();
    assert_eq!(js["stories"][0]["volume_loss"], 1.0);
    assert_eq!(js["stories"][1]["volume_loss"], 0.0);
}
