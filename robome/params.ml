type t = {
  body_radius : float;
  forward_speeds : float array;
  backward_speeds : float array;
  turn_rates : float array;
  angle_turn_rate : float;
  sound_duration : float;
  sound_gap : float;
  alert_latency : float;
  proximity_bands : float array;
  proximity_half_angle : float;
  edge_lookahead : float;
  camera_height : float;
  camera_hfov : float;
  camera_vfov : float;
  camera_min_range : float;
  qr_range_factor : float;
  qr_fraction : float;
  qr_max_view_angle : float;
  camera_latency : float;
  head_up_angle : float;
  head_down_angle : float;
  speed_noise : float;
  drift : float;
}

let deg d = d *. Float.pi /. 180.
let to_deg r = r *. 180. /. Float.pi

let default = {
  body_radius = 0.10;
  forward_speeds = [| 0.04; 0.07; 0.10; 0.13; 0.16 |];
  backward_speeds = [| 0.03; 0.05; 0.07; 0.10; 0.12 |];
  turn_rates = Array.map deg [| 30.; 45.; 60.; 75.; 90. |];
  angle_turn_rate = deg 60.;
  sound_duration = 0.10;
  sound_gap = 0.10;
  alert_latency = 0.10;
  proximity_bands = [| 0.2; 0.5; 1.0 |];
  proximity_half_angle = deg 15.;
  edge_lookahead = 0.05;
  camera_height = 0.30;
  camera_hfov = deg 60.;
  camera_vfov = deg 45.;
  camera_min_range = 0.15;
  qr_range_factor = 8.0;
  qr_fraction = 0.8;
  qr_max_view_angle = deg 60.;
  camera_latency = 0.05;
  head_up_angle = deg 20.;
  head_down_angle = deg (-30.);
  speed_noise = 0.03;
  drift = deg 1.0;
}

let noiseless p = { p with speed_noise = 0.; drift = 0. }
