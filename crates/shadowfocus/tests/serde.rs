//! The `serde` feature: inputs, settings and fitted maps survive a JSON
//! round trip unchanged, and a frustum is checked on the way in.

use glam::DVec3;
use shadowfocus::focus::{fit, ClipConvention, FocusResult, FocusSettings, MapFit, Method, Notes, ReceiverBoxes, SplitSettings};
use shadowfocus::geom::{Aabb, Camera, Frustum, Light};

fn round_trip<T: serde::Serialize + serde::de::DeserializeOwned>(value: &T) -> T {
    serde_json::from_str(&serde_json::to_string(value).unwrap()).unwrap()
}

#[test]
fn a_frame_round_trips_through_json() {
    let camera = Camera {
        eye: DVec3::new(3.0, 1.5, 4.0),
        forward: DVec3::new(-0.2, -0.05, -1.0),
        up: DVec3::Y,
        fovy: 1.2,
        aspect: 2.0,
        near: 0.1,
        far: 60.0,
    };
    let scene = Aabb::new(DVec3::new(-30.0, 0.0, -60.0), DVec3::new(30.0, 12.0, 10.0)).unwrap();
    // A sun, a point light inside the view (cube faces) and a spot light.
    let spot = Camera { eye: DVec3::new(-5.0, 10.0, -20.0), forward: DVec3::NEG_Y, up: DVec3::Z, ..camera };
    let lights = [
        Light::directional(DVec3::new(-0.3, -1.0, 0.6)).unwrap(),
        Light::point(DVec3::new(2.0, 3.0, -8.0)).unwrap(),
        Light::spot(spot.eye, Frustum::from_camera(&spot).unwrap()).unwrap(),
    ];
    let settings = FocusSettings {
        method: Method::Lispsm,
        splits: SplitSettings { count: 3, ..SplitSettings::default() },
        clip: ClipConvention::OPENGL.reversed(),
        ..FocusSettings::default()
    };
    assert_eq!(round_trip(&camera), camera);
    assert_eq!(round_trip(&scene), scene);
    assert_eq!(round_trip(&settings), settings);
    let mut out = FocusResult::new();
    let mut maps = 0;
    for light in lights {
        assert_eq!(round_trip(&light), light);
        fit(&round_trip(&camera), &round_trip(&light), &round_trip(&scene), &round_trip(&settings), &mut out).unwrap();
        assert_eq!(round_trip(&out.notes), out.notes);
        for map in out.maps() {
            let back: MapFit = round_trip(&map.fit);
            assert_eq!(back.clip_from_world.to_cols_array().map(f64::to_bits), map.fit.clip_from_world.to_cols_array().map(f64::to_bits));
            assert_eq!(back, map.fit);
            maps += 1;
        }
    }
    assert!(maps >= 3 + 6, "{maps} maps");
    assert_eq!(round_trip(&Notes::INVERTED), Notes::INVERTED);
}

#[test]
fn a_frustum_is_checked_on_the_way_in() {
    // Eight coincident corners are no frustum: an error, not a bad value.
    let flat = serde_json::to_string(&[[0.0f64; 3]; 8]).unwrap();
    let err = serde_json::from_str::<Frustum>(&flat).unwrap_err();
    assert!(err.to_string().contains("frustum"), "{err}");
    let cam = Camera { eye: DVec3::ZERO, forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.0, near: 1.0, far: 10.0 };
    let f = Frustum::from_camera(&cam).unwrap();
    assert_eq!(round_trip(&f), f);
}

#[test]
fn receiver_boxes_keep_their_kind() {
    // Solids serialise as a list of boxes (as before there were boxes of
    // seen points), seen points as `{"seen": [...]}`; bad boxes are refused.
    let b = [Aabb::new(DVec3::ZERO, DVec3::ONE).unwrap(), Aabb::new(DVec3::splat(2.0), DVec3::splat(3.0)).unwrap()];
    let solid = ReceiverBoxes::new(&b).unwrap();
    let seen = ReceiverBoxes::seen(&b).unwrap();
    assert!(serde_json::to_string(&solid).unwrap().starts_with('['));
    assert!(serde_json::to_string(&seen).unwrap().starts_with("{\"seen\""));
    assert_eq!(round_trip(&solid), solid);
    assert_eq!(round_trip(&seen), seen);
    assert!(round_trip(&seen).is_seen() && !round_trip(&solid).is_seen());
    let settings = FocusSettings { receivers: seen, ..FocusSettings::default() };
    assert_eq!(round_trip(&settings), settings);
    assert_eq!(serde_json::from_str::<ReceiverBoxes>(r#"{"seen": []}"#).unwrap(), ReceiverBoxes::NONE, "no boxes: no hint");
    assert_eq!(ReceiverBoxes::seen(&[]).unwrap(), ReceiverBoxes::NONE);
    let bad = r#"{"seen": [{"min": [0, 0, 0], "max": [1, -1, 1]}]}"#;
    let err = serde_json::from_str::<ReceiverBoxes>(bad).unwrap_err();
    assert!(err.to_string().contains("receiver box"), "{err}");
}
