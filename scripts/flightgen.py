#!/usr/bin/python3
"""Independent flight generator: synthetic measured data in the project's CSV interchange formats
(landing radar: docs/diagnosis.md, "Measured data"; azimuth-only: docs/adsb-and-camera-bearings.md;
multi-sensor: docs/autoferry-multi-sensor.md) flown on trajectories the simulator never flies. It
shares no code with sim/, estimators/ or common/: its own WGS84 geodesy, kinematics, error models
and random streams.

  scripts/flightgen.py landing OUTDIR [--seed N] [--noise-seed N] [--set key=value ...]   site.json radar.csv nav.csv truth.csv
  scripts/flightgen.py uav OUTDIR [--seed N] [--noise-seed N] [--set key=value ...]       observer.csv bearings.csv truth.csv
  scripts/flightgen.py shipradar OUTDIR [--seed N] [--noise-seed N] [--set key=value ...] observer.csv detections.csv truth.csv [targets.csv]
  scripts/flightgen.py landing|uav|shipradar --list-keys                 every key: default, range, unit
As a module: landing(outdir, seed, overrides, noise_seed), uav(...) and shipradar(...)
(noise_seed None: seed; it seeds the noise streams alone, so one geometry takes many noise draws) write the files and
return {"params": every key's value and the derived ones (the truth), "files", "truth", "nav" |
"observer", "plots" | "bearings" | "detections": the unrounded rows} (shipradar also "targets": each
target's drawn motion, hull, mooring, AIS and noise; "illuminations": every illumination with its
target; "sources": beside each detection row its origin, ("ship", (ids...)) (more than one id:
unresolved echoes merged), ("clutter",), ("sea",) or ("land", j); "land": the reflectors' (lat, lon)).
Prints the params as JSON on stdout.
Same seed and keys: byte-identical files. Random streams: Python's random.Random seeded with the
string "flightgen:MODE:SEED:STREAM" (streams geometry, nav, white, outlier, coloured.CHANNEL; shipradar's
below). The random defaults are drawn from `geometry` in the table's order whether overridden or not, so
setting one key leaves every other draw as it was.

Geodesy (WGS84: a = 6378137 m, f = 1/298.257223563, e2 = f (2 - f), N = a / sqrt(1 - e2 sin^2 lat)):
  X = (N + h) cos lat cos lon,  Y = (N + h) cos lat sin lon,  Z = (N (1 - e2) + h) sin lat;
  inverse: lon = atan2(Y, X), p = hypot(X, Y), lat <- atan2(Z + e2 N sin lat, p) 10 times from
  atan2(Z, p (1 - e2)), h = p cos lat + Z sin lat - a sqrt(1 - e2 sin^2 lat);
  ENU at (lat0, lon0): [e n u] = M (P - P0), rows (-sin lon0, cos lon0, 0),
  (-sin lat0 cos lon0, -sin lat0 sin lon0, cos lat0), (cos lat0 cos lon0, cos lat0 sin lon0, sin lat0).
A horizontal point (e, n) of a local flat-earth frame is mapped to the ellipsoid along the normal
through (e, n, 0) (ENU -> ECEF -> geodetic) and given its ellipsoidal height explicitly.

Landing kinematics: step dt = 0.1 s (truth and nav at 10 Hz), forward Euler in the tangent plane at
the runway threshold; height h above the threshold is ellipsoidal (level flight stays level):
  e += dt v sin psi,  n += dt v cos psi,  h += dt hdot;
  psi_dot = clamp(10/s wrap(psi_cmd - psi), +-turn_rate_dps);   hdot += clamp(hdot_cmd - hdot, +-1 m/s^2 dt),
  hdot_cmd = clamp(hdot_ff + 0.1/s (h_cmd - h), +-20 m/s);
  v(t) = speed0 before t_d = decel_start_s, speed0 + (speed1 - speed0)(t - t_d)/decel_s, speed1 after
  (intercept and turns; straight and level fly speed0).
Runway frame: course chi = heading_deg; x = -(e sin chi + n cos chi) out along the approach,
y = e cos chi - n sin chi right of the centreline. Glide path h_cmd = min(level_h_m, 15 m + x tan gamma),
hdot_ff = tan(gamma) dx/dt on its sloping part. Centreline pursuit psi_cmd = chi - atan(y / 1500 m).
An approach ends once x <= 300 m, any flight at duration_s. start_x_m = auto puts the start so that
the planned path (speed schedule summed over duration_s) ends at x = 300 m at duration_s.
  intercept: start at (start_x_m, y0), y0 = sgn(a) (first_leg_m sin|a| + r (1 - cos a)), r = v/omega,
    a = intercept_deg, psi = chi - a; a turn at omega = turn_rate_dps starts once |y| <= r (1 - cos(psi - chi))
    and ends on the course, then pursuit.
  straight: on the centreline from start_x_m. turns: pursuit, and from 0.2 duration_s the heading
    chi + turn_deg, chi - turn_deg, ... (n_turns legs of turn_hold_s, the inner ones twice as long, so
    y returns to ~0), then pursuit.
  level: a straight pass at level_h_m: closest approach |pass_dist_m| from the radar at bearing
    azimuth_reference + pass_angle_deg, at duration_s / 2; heading that bearing + 90 deg (- if pass_dist_m < 0).
Radar site: (e, n) = radar_along_m f + radar_lateral_m r (f along the runway, r right of it),
h = threshold + radar_height_m; azimuth_reference_deg = heading_deg + 180 + az_ref_offset_deg.

Radar plots at t = 0, 1/rate_hz, ... <= flight end, errors applied to the TRUE polar coordinates at
t - tau (tau = time_offset_s; truth interpolated linearly in ECEF between its 0.1 s samples):
  [e n u] = aircraft in ENU at the radar antenna, R = |[e n u]|, E = atan2(u, hypot(e, n)),
  A = wrap(atan2(e, n) - azimuth_reference_deg) in (-180, 180]; a plot only if |A| < 60 and 0.1 <= E <= 30 deg.
  R_m = (1 + g) R + b_R + d_R t + S_R H(t - t_s) + nu_R
  A_m = wrap(A + c tan E + b_A + d_A t + S_A H(t - t_s) + nu_A)
  E_m = E + k cot E + b_E + d_E t + S_E H(t - t_s) + nu_E
  g range_gain, c coupling_rad, k refraction_rad (radians, shown in deg), b_* biases, d_* drifts;
  S_X = step_size on step_channel only, H the unit step, t_s = step_time_frac * flight end.
  nu_X = sigma_X (w_X + f u_X(t)), w ~ N(0, 1) white, u unit-variance coloured noise (f = coloured_sigma_frac,
  none if coloured_tau_s = 0); an outlier plot (probability outlier_prob, all channels) has
  nu_X = outlier_scale sigma_X w'_X.
  gm: u_k = phi u_(k-1) + sqrt(1 - phi^2) w_k, phi = exp(-(t_k - t_(k-1)) / tau_c), u_0 ~ N(0, 1) (exact, any steps).
  cascade: on a 0.01 s grid, a = exp(-0.01 / (tau_c / 2)): f1 <- a f1 + sqrt(1 - a^2) w, f2 <- a f2 + (1 - a) f1,
    u = f2 (1 + a) / sqrt(1 + a^2); started in its stationary law f1 ~ N(0, 1), f2 = (f1 + a z) / (1 + a).
Nav (10 Hz, per axis of the aircraft's local ENU): eps_k = phi eps_(k-1) + sigma sqrt(1 - phi^2) w_k,
  phi = exp(-0.1 s / nav_tau_s), eps_0 ~ N(0, sigma^2); nav = truth + eps + nav_white_m w'.

UAV: the boat at sea level (h = 0), (e, n) = boat_speed t (sin, cos)(boat_heading) in the site's ENU.
Observer at height_m, centre c = boat(t) (centre=follow) or boat(0) (fixed), path position p(s) about c,
arc length s = P start_frac + speed_mps t (- for ccw/reversed; speed relative to the centre):
  orbit: R (sin th, cos th), th = s / R (clockwise for cw). racetrack along track_deg: legs leg_m long at
  +-R from its axis joined by half-circles of radius R. figure8: circles of radius R centred at
  +-R along track_deg from a crossing point R to the right of the boat's side of the axis.
  Bearing beta = atan2(e, n) of the boat in the observer's ENU, both at t - tau; written wrapped to [0, 360):
  beta_m = beta + b + d t + nu, nu = sigma_deg w + coloured_sigma_deg u(t) (outlier: outlier_scale sigma_deg w').
  observer.csv = truth + GM error (obs_nav_sigma_m, obs_nav_tau_s) per ENU axis; truth and observer at 10 Hz.
Ship radar (shipradar): a north-stabilised rotating marine radar (sensor name radar) on a slowly
moving own ship, surface target ships and an AIS-like reference, in the multi-sensor folder format
(observer.csv t_s,lat_deg,lon_deg,h_m,heading_deg; detections.csv t_s,sensor,range_m,bearing_deg;
truth.csv t_s,target,lat_deg,lon_deg, no height: surface targets). Every track lies in one flat
east-north plane about (lat_deg, lon_deg), mapped to the ellipsoid as above: targets at h = 0, the
antenna at h = antenna_h_m.
  Tracks (own ship and targets): constant speed v, legs of constant course c joined by turns at a
  constant rate w, exact at any t (tau = t - segment start): a leg e = e0 + v tau sin c,
  n = n0 + v tau cos c; a turn c = c0 + w tau, e = e0 + v/w (cos c0 - cos c), n = n0 + v/w (sin c - sin c0).
  Before t = 0 the first leg extends backwards.
  Own ship: from (0, 0) on obs_course_deg at obs_speed_mps; turn k = 1..obs_turns starts at
  k duration_s / (obs_turns + 1) (or when turn k - 1 ends) and changes the course by
  obs_turn_deg (-1)^(k-1) at obs_turn_rate_dps. observer.csv at t = 0, 1, ... <= duration_s s: the
  antenna's position (no nav error) and heading_deg = its course (no crab).
  Target i = 1..n_targets, from its own stream target.i (all drawn, in this order, whatever the keys,
  so another n_targets keeps the first targets): distance U[target_min_range_m, target_max_range_m]
  and bearing U[0, 360) from the own ship at t_p = place_time_frac duration_s; speed
  U[target_min_speed_mps, target_max_speed_mps]; course U[0, 360); one turn with probability
  turn_fraction: start U[0.1, 0.8] duration_s, course change +-U[20, 90] deg at U[0.1, 0.5] deg/s.
  Radar: scan k = 0 .. K-1 covers [k P, (k+1) P), P = scan_period_s, K = floor(duration_s / P); the
  beam's true bearing is theta(t) = beta0 + omega (t - k P), omega = 360/P deg/s, beta0 =
  scan_start_bearing_deg (clockwise sweep, north-stabilised). [e n u] = target in the antenna's ENU
  at t, r = |[e n u]| (slant), beta = atan2(e, n). A target is illuminated at every t with
  theta(t) = beta(t) (mod 360), i.e. t = k P + ((beta(t) - beta0) mod 360)/omega, solved by
  t <- t + wrap180(beta(t) - theta(t))/omega until the step is below 1e-7 s (the first from scan 0's
  t = ((beta(0) - beta0) mod 360)/omega, the next from the last one plus its spacing, clamped to
  [P/2, 3P/2]); a target crossing beta0 may be lit twice or not at all within one scan's window.
  n_unresolved (params) counts iterations that failed (only a target passing within a few metres).
  Each illumination draws u_d, w_r, w_b (streams detect.i, white.i; in or out of range) and is a
  detection if min_range_m <= r <= max_range_m and u_d < p_detect:
    range_m = (1 + range_gain) r + range_bias_m + range_sigma_m w_r     (not written if <= 0)
    bearing_deg = (beta + bearing_bias_deg + bearing_sigma_deg w_b) mod 360, in [0, 360)
    t_s = t + time_offset_s (stamp = illumination), or (k+1) P + time_offset_s (stamp = scan: every
    detection of scan k stamped at its sweep's end, latency ((beta0 - beta) mod 360)/omega in (0, P]).
  Clutter (stream clutter): per scan Poisson(clutter_per_scan) false detections, range
  U[max(min_range_m, 1), max_range_m], bearing U[0, 360), stamped as a target at that bearing
  (illumination t = k P + ((bearing - beta0) mod 360)/omega). Rows sorted by t_s, ties by bearing;
  no target ids. Drawn as measured values: range_gain and the biases would only move the uniform
  law's limits (and the files must stay as they were); the sea clutter below takes them.
  truth.csv (AIS): target i reports at t_1 = u D_1, t_(j+1) = t_j + D_(j+1), D ~ U[ais_min_s, ais_max_s],
  u ~ U[0, 1) (stream ais_times.i), while t <= duration_s; the report stamped t gives the position at
  t - ais_time_offset_s plus ais_sigma_m (w_e, w_n) in the plane (stream ais_noise.i). Rows sorted
  by t_s, then target id. Noise streams (--noise-seed): detect.i, white.i, clutter, ais_noise.i,
  sea_clutter, land.j; every other stream from --seed.
  Scenes (scene): open keeps the table's defaults (point targets 2-12 km away, white noise, no
  clutter, land, moored ships or merged echoes: the files exactly as before the keys below
  existed); harbour takes the defaults of "Scene harbour" below instead (a key given with --set
  wins), a busy harbour as a real recording shows it. Each feature below is off at its open default.
  Hulls (hull_max_length_m > 0; stream hull.i): length L = hull_min_length_m (hull_max_length_m /
  hull_min_length_m)^u (log-uniform), beam B = max(3 m, L U[0.12, 0.2]); the AIS antenna A =
  U[0.15, 0.85] L behind the bow on the centreline and C = U[0.2, 0.8] B from the port side (AIS
  static data A, B = L - A to the stern, C, D = B - C to starboard). The track is the antenna's, and
  the truth reports it. The hull is the rectangle x in [A - L, A] ahead of, y in [-C, B - C] to
  starboard of the antenna, in the tangent plane at the antenna (h = 0), heading = the true bearing
  there of the track's course (the plane's course turned by the meridian convergence, about
  dE tan(lat) / a: 0.35 deg 20 km east of the site at 63 deg N). Its echo: with q(x, y) the hull
  point in the radar antenna's ENU, q0 = q(A, -C), a = q(A, B - C) - q0, b = q(A - L, -C) - q0
  (orthogonal), range r = |q0 + s a + t b|, s = clamp(-q0.a / a.a), t = clamp(-q0.b / b.b) into
  [0, 1] (the rectangle's nearest point, slant: its leading edge); bearing beta = beta_c +
  (min_j d_j + max_j d_j) / 2, d_j = wrap180(bearing of corner j - beta_c), beta_c the bearing of the
  hull's centre (the middle of its angular extent; beta_c itself if the radar is over the hull).
  This r and beta replace the point's in the illumination and the detection (a point target, L = 0:
  the antenna's as above). End-on a long hull's range is up to 0.85 L short of the antenna's,
  broadside about C or D; it is never short by less than min(A, L - A, C, D).
  Moored ships (stream moor.i: u_m, u_s, u_g): u_m < moored_fraction lies still (speed 0, no turn:
  those target.i draws unused), heading its drawn course. Moored ships in id order fill clusters:
  one opens a cluster of 2 + floor(u_s (cluster_max - 1)) ships (1 if cluster_max = 1) and is placed
  as any ship; the next moored ships join it until it is full (the last cluster may stay short), each
  parallel to the previous one (same heading) on its starboard side: hull centre = the previous
  one's + ((B_prev + B) / 2 + 1 m + 2 m u_g) to starboard, laid out in the plane (alongside, not
  overlapping). Cluster id = the id of its first ship; adding targets keeps the earlier ones
  except the members of the last cluster.
  Placement with hulls or land: every hull of a ship (a cluster: all of them) at t_p must keep its
  centre its half diagonal + 10 m short of the shore line, and with hulls its circle (centre, half
  diagonal) must not meet those of the ships placed before (id order). A draw on land is first
  mirrored across the line through the own ship parallel to the shore (distance kept); a draw that
  still fails is replaced by distance and bearing from stream place.i, up to 49 times, the last
  kept. Only at t_p: moving ships may later pass through hulls and ashore (no collision avoidance).
  Noise per ship (stream sigma.i, fixed with the geometry): bearing sigma U[bearing_sigma_deg,
  bearing_sigma_max_deg], range sigma U[range_sigma_m, range_sigma_max_m], each Gauss-Markov over
  the ship's illuminations (noise_tau_s > 0): x_1 = sigma w_1, x_k = phi x_(k-1) + sqrt(1 - phi^2)
  sigma w_k, phi = exp(-(t_k - t_(k-1)) / noise_tau_s), w the white.i draws above (noise_tau_s = 0:
  x_k = sigma w_k, the white noise above); x replaces sigma w in range_m and bearing_deg.
  Unresolved echoes: detected echoes of one scan k closer than range_resolution_m in true range
  AND beamwidth_deg in true bearing are linked (single linkage), and each linked group is one
  detection at the mean of its echoes weighted by hull length (1 for a point target) of t, r,
  beta (about the first's) and the noises, then the errors above (0: every echo its own detection).
  Ship echoes only: land and clutter are never merged.
  Sea clutter (stream sea_clutter): per scan Poisson(sea_clutter_per_scan) returns at true range
  r0 - s ln(1 - u (1 - exp(-(max_range_m - r0) / s))) (exponential, scale s = sea_clutter_scale_m,
  from r0 = min_range_m, truncated at max_range_m) and true bearing U[0, 360), lit at k P +
  ((bearing - beta0) mod 360) / omega: range (1 + range_gain) r + range_bias_m, bearing +
  bearing_bias_deg, stamp as a target's (no noise: their places are random).
  Land: a straight shore land_distance_m from the own ship's start, perpendicular to the bearing
  land_bearing_deg (auto: obs_course_deg - 90 deg sgn(obs_turn_deg), abeam on the side away from
  the first turn: the own course alternates between obs_course_deg and obs_course_deg +
  obs_turn_deg, so the own ship never closes the shore); land_points reflectors on it at h = 0,
  U[-land_half_length_m, land_half_length_m] along it from the foot of that normal (stream
  land_points). Each scan, a reflector within [min_range_m, max_range_m] is detected with
  probability land_p_detect (stream land.j: u, w_r, w_b drawn every scan) with the white noise
  range_sigma_m, bearing_sigma_deg and the radar's errors as a target; it is lit once a scan where theta(t) =
  beta(t), r and beta quadratic in t through their exact values at the scan's start, middle and
  end (off by terms in (v P / r)^3: < 3e-5 deg and 0.1 mm at 500 m from an own ship at 6 m/s).
  Clutter, sea clutter and land have no truth rows.
  AIS: ais_whole_seconds = 1: t_1 = ceil(u D_1), t_(j+1) = t_j + max(1, round(D_(j+1))) (half up),
  whole seconds, each the antenna's position at that second (minus ais_time_offset_s). Stream
  ais_static.i (u_s, u_w, v_L, v_B): u_s < ais_silent_fraction: the ship sends nothing (no truth or
  targets.csv rows; still on the radar); u_w < ais_wrong_dims_fraction: its static data are wrong:
  L' = min(1000 m, f_L L), B' = f_B B, f = 0.3 + 2.7 v (U[0.3, 3]), A' = A L'/L, C' = C B'/B (the
  antenna in the same place of the stated hull; 1000 m: the diagnosis reader's bound); else the
  true L, B, A, C. targets.csv (hulls only): target,length_m,beam_m,to_bow_m,to_port_m, one row per
  ship with AIS in id order, whole metres as AIS sends them: round(L'), round(B'), round(A'), round(C').
Default tokens: U[a,b] uniform, +-U[a,b] with a random sign, U{a,b} one of, auto derived.

Keys (landing):
    geometry          intercept     {intercept|straight|level|turns}  -    trajectory (above)
    duration_s        U[400,600]    [30,7200]        s      flight end time (an approach may end earlier)
    lat_deg           U[-60,60]     [-89,89]         deg    runway threshold latitude
    lon_deg           U[-180,180]   [-180,180]       deg    runway threshold longitude
    threshold_h_m     U[0,500]      [-400,5000]      m      threshold ellipsoidal height
    heading_deg       U[0,360]      [0,360]          deg    runway heading = approach course
    radar_lateral_m   +-U[100,300]  [-5000,5000]     m      radar right (+) of the centreline
    radar_along_m     U[200,1500]   [-5000,5000]     m      radar past the threshold along the runway
    radar_height_m    U[0,20]       [-100,500]       m      antenna above the threshold
    az_ref_offset_deg U[0,10]       [-90,90]         deg    azimuth reference minus the reciprocal heading
    speed0_mps        80            [20,300]         m/s    ground speed at the start
    speed1_mps        65            [20,300]         m/s    ground speed after the deceleration
    decel_s           60            [1,3600]         s      deceleration time
    decel_start_s     auto          [0,7200]         s      deceleration start (auto: U in the middle third)
    level_h_m         U[600,900]    [30,10000]       m      level flight height above the threshold
    glide_deg         3             [1,10]           deg    glide path angle
    start_x_m         auto          [500,200000]     m      start distance out along the approach
    intercept_deg     +-U[20,45]    [-80,80]         deg    first-leg heading off the course (+: from the right)
    first_leg_m       U[2000,6000]  [0,100000]       m      intercept: first leg length before the turn
    turn_rate_dps     U[1.5,3]      [0.3,10]         deg/s  turn rate bound
    turn_deg          +-U[20,30]    [-60,60]         deg    turns: heading offset of the first S-turn leg
    n_turns           U{2,3}        int[1,5]         -      turns: number of S-turn legs
    turn_hold_s       30            [5,300]          s      turns: first and last leg duration
    pass_dist_m       +-U[8000,15000]  [-60000,60000]  m    level: signed closest approach to the radar
    pass_angle_deg    U[-20,20]     [-60,60]         deg    level: closest-approach bearing off the reference
    rate_hz           1             [0.1,20]         Hz     radar plot rate
    sigma_range_m     12            [0,1000]         m      white noise
    sigma_az_deg      0.25          [0,10]           deg    white noise
    sigma_el_deg      0.30          [0,10]           deg    white noise
    coloured_tau_s    0             [0,2000]         s      coloured noise time constant (0: none)
    coloured_sigma_frac 0.5         [0,10]           -      coloured std / white sigma
    coloured_kind     gm            {gm|cascade}     -      coloured noise kind
    range_bias_m      0             [-1000,1000]     m      constant bias
    az_bias_deg       0             [-10,10]         deg    constant bias
    el_bias_deg       0             [-10,10]         deg    constant bias
    time_offset_s     0             [-20,20]         s      tau: a plot stamped t shows the aircraft at t - tau
    range_gain        0             [-0.1,0.1]       -      g
    refraction_rad    0             [-0.01,0.01]     rad    k
    coupling_rad      0             [-0.1,0.1]       rad    c
    step_channel      elevation     {range|azimuth|elevation}  -  channel of the bias step
    step_size         0             [-1000,1000]     m|deg  bias step
    step_time_frac    0.5           [0,1]            -      step time / flight end
    range_drift_mps   0             [-10,10]         m/s    drift
    az_drift_degps    0             [-0.1,0.1]       deg/s  drift
    el_drift_degps    0             [-0.1,0.1]       deg/s  drift
    outlier_prob      0             [0,1]            -      probability of an outlier plot
    outlier_scale     10            [0,1000]         -      outlier noise / white sigma
    nav_sigma_m       1.9           [0,100]          m      nav Gauss-Markov std per axis
    nav_tau_s         120           [0.1,100000]     s      nav Gauss-Markov time constant
    nav_white_m       0.3           [0,100]          m      nav white noise std per axis

Keys (uav):
    geometry          orbit         {orbit|racetrack|figure8}  -  observer path (above)
    centre            follow        {follow|fixed}   -      path centre follows the boat or stays at its start
    direction         U{cw,ccw}     {cw|ccw}         -      sense of travel
    duration_s        300           [10,7200]        s      flight duration
    rate_hz           2             [0.1,50]         Hz     bearing rate
    lat_deg           U[-60,60]     [-89,89]         deg    boat start latitude
    lon_deg           U[-180,180]   [-180,180]       deg    boat start longitude
    boat_speed_mps    U[2,8]        [0,50]           m/s    boat speed (constant)
    boat_heading_deg  U[0,360]      [0,360]          deg    boat course
    radius_m          U[600,1500]   [100,20000]      m      orbit / turn radius R
    height_m          U[100,300]    [10,10000]       m      observer ellipsoidal height
    speed_mps         25            [1,300]          m/s    observer speed relative to the centre
    leg_m             U[1000,2000]  [0,50000]        m      racetrack straight leg length
    track_deg         U[0,360]      [0,360]          deg    racetrack / figure8 axis bearing
    start_frac        U[0,1]        [0,1]            -      start position as a fraction of the path
    obs_nav_sigma_m   1             [0,100]          m      observer nav Gauss-Markov std per axis
    obs_nav_tau_s     60            [0.1,100000]     s      observer nav Gauss-Markov time constant
    sigma_deg         0.5           [0,20]           deg    white noise
    coloured_tau_s    0             [0,2000]         s      coloured noise time constant (0: none)
    coloured_sigma_deg 0.3          [0,20]           deg    coloured noise std
    coloured_kind     gm            {gm|cascade}     -      coloured noise kind
    bias_deg          0             [-20,20]         deg    constant bias
    time_offset_s     0             [-20,20]         s      tau
    drift_degps       0             [-0.1,0.1]       deg/s  drift
    outlier_prob      0             [0,1]            -      probability of an outlier bearing
    outlier_scale     10            [0,1000]         -      outlier noise / sigma_deg

Keys (shipradar):
    scene             open          {open|harbour}   -      preset of defaults (harbour: "Scene harbour" below)
    duration_s        3600          [60,86400]       s      run length (scans lie within it)
    lat_deg           63.46         [-89,89]         deg    own ship start latitude (default: Trondheimsfjord)
    lon_deg           10.40         [-180,180]       deg    own ship start longitude
    antenna_h_m       15            [0,100]          m      radar antenna ellipsoidal height (observer.csv h_m)
    obs_speed_mps     U[2,6]        [0,15]           m/s    own ship speed (constant)
    obs_course_deg    U[0,360]      [0,360]          deg    own ship initial course
    obs_turns         U{1,2}        int[0,10]        -      own ship course changes
    obs_turn_deg      +-U[30,90]    [-180,180]       deg    first course change (+: clockwise); the next alternate in sign
    obs_turn_rate_dps 0.5           [0.05,5]         deg/s  own ship turn rate
    n_targets         40            int[1,200]       -      target ships (ids 1..n_targets)
    target_min_range_m 2000         [0,50000]        m      nearest distance drawn for a target at place_time_frac
    target_max_range_m 12000        [0,50000]        m      farthest distance drawn for a target at place_time_frac
    place_time_frac   0.5           [0,1]            -      time (/ duration_s) at which the target distances hold
    target_min_speed_mps 0          [0,30]           m/s    slowest target
    target_max_speed_mps 10         [0,30]           m/s    fastest target
    turn_fraction     0.3           [0,1]            -      probability that a target makes one gentle turn
    scan_period_s     2.5           [0.5,20]         s      antenna rotation period P
    scan_start_bearing_deg 0        [0,360]          deg    beta0: true bearing of the beam at each scan start
    max_range_m       12000         [100,100000]     m      no detection beyond (slant range)
    min_range_m       50            [0,5000]         m      no detection nearer (blind zone)
    p_detect          0.9           [0,1]            -      detection probability of an illuminated target in range
    range_sigma_m     15            [0,1000]         m      white noise (each ship: its lowest sigma)
    bearing_sigma_deg 0.5           [0,20]           deg    white noise (each ship: its lowest sigma)
    bearing_sigma_max_deg auto      [0,20]           deg    each ship's sigma U[bearing_sigma_deg, this] (auto: = it)
    range_sigma_max_m auto          [0,1000]         m      each ship's sigma U[range_sigma_m, this] (auto: = it)
    noise_tau_s       0             [0,100000]       s      ship noise Gauss-Markov correlation time (0: white)
    clutter_per_scan  0             [0,100]          1/scan mean number (Poisson) of false detections per scan
    stamp             illumination  {illumination|scan}  -  detection time stamp: illumination or sweep end
    time_offset_s     0             [-20,20]         s      stamp minus the true (illumination or sweep-end) time
    range_bias_m      0             [-1000,1000]     m      constant bias
    range_gain        0             [-0.1,0.1]       -      g: range_m = (1 + g) r + bias
    bearing_bias_deg  0             [-20,20]         deg    constant bias
    ais_min_s         2             [0.05,600]       s      shortest AIS report interval
    ais_max_s         10            [0.05,600]       s      longest AIS report interval
    ais_sigma_m       0             [0,1000]         m      AIS position white noise per axis (east, north)
    ais_time_offset_s 0             [-60,60]         s      an AIS report stamped t gives the position at t - offset
    ais_whole_seconds 0             int[0,1]         -      1: AIS reports on whole seconds, intervals rounded (>= 1 s)
    ais_silent_fraction 0           [0,1]            -      probability that a ship sends no AIS (radar only)
    ais_wrong_dims_fraction 0       [0,1]            -      probability that a ship's AIS static data are wrong
    hull_min_length_m 10            [8,460]          m      shortest hull (log-uniform between the two)
    hull_max_length_m 0             [0,460]          m      longest hull (0: point targets, no targets.csv)
    moored_fraction   0             [0,1]            -      probability that a ship is moored (at rest, in a cluster)
    cluster_max       1             int[1,10]        -      most ships moored side by side in one cluster (1: each alone)
    range_resolution_m 0            [0,1000]         m      echoes closer in range and bearing merge (0: never)
    beamwidth_deg     0             [0,10]           deg    echoes closer in bearing and range merge (0: never)
    sea_clutter_per_scan 0          [0,100]          1/scan mean number (Poisson) of sea clutter returns per scan
    sea_clutter_scale_m 1500        [1,100000]       m      sea clutter range scale (exponential from min_range_m)
    land_points       0             int[0,2000]      -      fixed reflectors on a straight shore (0: no land)
    land_distance_m   3000          [50,100000]      m      shore distance from the own ship's start
    land_bearing_deg  auto          [0,360]          deg    shore normal from the own start (auto: abeam, off the turn)
    land_half_length_m 4000         [0,100000]       m      reflectors spread over +- this along the shore
    land_p_detect     0.7           [0,1]            -      detection probability of a land reflector in range, per scan

Scene harbour (shipradar scene=harbour: these defaults instead; n_targets 40, min_range_m 50 and
max_range_m 12000 as in open; a key given with --set wins):
    target_min_range_m 250
    target_max_range_m 9000
    bearing_sigma_max_deg 1.5
    range_sigma_max_m 80
    noise_tau_s       20
    ais_whole_seconds 1
    ais_silent_fraction 0.1
    ais_wrong_dims_fraction 0.1
    hull_max_length_m 300
    moored_fraction   0.4
    cluster_max       4
    range_resolution_m 30
    beamwidth_deg     1.5
    sea_clutter_per_scan 8
    land_points       30

(An hour of it holds about 70 000 detections: about 40 000 of ships, 20 000 of land, 10 000 of sea
clutter: a plot extractor's output with land mostly masked, not every land cell.)
"""
import bisect
import json
import math
import os
import random
import re
import sys

from rnav import cli_args

PROG = "flightgen.py"
A_WGS, F_WGS = 6378137.0, 1 / 298.257223563
E2 = F_WGS * (2 - F_WGS)
DT = 0.1                # trajectory, truth and nav step [s]
END_X_M = 300.0         # an approach ends this far before the threshold
TCH_M = 15.0            # glide path height over the threshold
LOOKAHEAD_M = 1500.0    # centreline pursuit
CASCADE_DT = 0.01       # cascade noise grid [s]


class BadInput(ValueError):
    """A bad key, value or OUTDIR (the CLI's exit status 2)."""


# ---------------------------------------------------------------- geodesy
def to_ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A_WGS / math.sqrt(1 - E2 * math.sin(la) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (1 - E2) + h) * math.sin(la))


def to_geodetic(x, y, z):
    # (the generator's inner loop: math's functions bound locally, the same operations in order)
    sin, sqrt, atan2 = math.sin, math.sqrt, math.atan2
    p = math.hypot(x, y)
    lat = atan2(z, p * (1 - E2))
    for _ in range(10):
        s = sin(lat)
        lat = atan2(z + E2 * A_WGS / sqrt(1 - E2 * s * s) * s, p)
    s, c = sin(lat), math.cos(lat)
    return math.degrees(lat), math.degrees(atan2(y, x)), p * c + z * s - A_WGS * sqrt(1 - E2 * s * s)


class Frame:
    """Local ENU at a geodetic point."""

    def __init__(self, lat, lon, h):
        la, lo = math.radians(lat), math.radians(lon)
        self.o = to_ecef(lat, lon, h)
        self.m = ((-math.sin(lo), math.cos(lo), 0.0),
                  (-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)),
                  (math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)))

    # enu and ecef are the generator's inner loop: written out, each sum in the order (and from
    # the 0 start) of sum() over range(3), so the results are the same to the bit
    def enu(self, p):
        o, m = self.o, self.m
        d0, d1, d2 = p[0] - o[0], p[1] - o[1], p[2] - o[2]
        return tuple(0.0 + r[0] * d0 + r[1] * d1 + r[2] * d2 for r in m)

    def ecef(self, v):
        o, (m0, m1, m2) = self.o, self.m
        v0, v1, v2 = v[0], v[1], v[2]
        return (o[0] + (0.0 + v0 * m0[0] + v1 * m1[0] + v2 * m2[0]), o[1] + (0.0 + v0 * m0[1] + v1 * m1[1] + v2 * m2[1]),
                o[2] + (0.0 + v0 * m0[2] + v1 * m1[2] + v2 * m2[2]))

    def place(self, e, n, h):
        """(lat, lon, h, ECEF) of the horizontal point (e, n) mapped to the ellipsoid, at height h."""
        lat, lon, _ = to_geodetic(*self.ecef((e, n, 0.0)))
        return lat, lon, h, to_ecef(lat, lon, h)


def wrap180(a):
    r = math.fmod(a + 180.0, 360.0)
    return (r + 360.0 if r <= 0 else r) - 180.0


def polar(frame, p):
    """(range, bearing clockwise from north, elevation) of ECEF point p from frame's origin."""
    e, n, u = frame.enu(p)
    return math.sqrt(e * e + n * n + u * u), math.degrees(math.atan2(e, n)), math.degrees(math.atan2(u, math.hypot(e, n)))


def interp(samples, t):
    """ECEF at time t from samples at k DT (linear); None outside them."""
    f = t / DT
    j = round(f)
    if abs(f - j) < 1e-6:
        return samples[j] if 0 <= j < len(samples) else None
    i = math.floor(f)
    if i < 0 or i + 1 >= len(samples):
        return None
    w = f - i
    return tuple(a + w * (b - a) for a, b in zip(samples[i], samples[i + 1]))


# ---------------------------------------------------------------- keys
def _table(section):
    keys = {}
    for line in __doc__.split("Keys (%s):\n" % section, 1)[1].splitlines():
        if not line.strip():
            break
        name, dflt, rng, unit, desc = re.match(r" {4}(\w+) +(\S+) +(\S+) +(\S+) +(.*)$", line).groups()
        keys[name] = dict(default=dflt, range=rng, unit=unit, line=line.strip())
    return keys


KEYS = {"landing": _table("landing"), "uav": _table("uav"), "shipradar": _table("shipradar")}


def _scene(mode, name):
    """{key: default} of the docstring's "Scene NAME (MODE ...)" list."""
    out = {}
    for line in __doc__.split("Scene %s (%s" % (name, mode), 1)[1].split(":\n", 1)[1].splitlines():
        if not line.strip():
            break
        key, value = re.match(r" {4}(\w+) +(\S+)$", line).groups()
        out[key] = value
    return out


# A key's default per scene (the table's unless the scene's list names it); modes without a scene key have none.
SCENES = {"shipradar": {"open": {}, "harbour": _scene("shipradar", "harbour")}}


def check_value(keys, name, value):
    k = keys[name]
    if k["range"].startswith("{"):
        choices = k["range"][1:-1].split("|")
        if str(value) not in choices:
            hint = cli_args.closest(str(value), choices)
            raise BadInput("key %s: value '%s' is not one of %s%s" % (name, value, ", ".join(choices),
                            " (did you mean '%s'?)" % hint if hint else ""))
        return str(value)
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise BadInput("key %s: value '%s' is not a number" % (name, value))
    if not math.isfinite(x):
        raise BadInput("key %s: value '%s' is not a finite number" % (name, value))
    is_int, lo, hi = re.fullmatch(r"(int)?\[(\S+),(\S+)\]", k["range"]).groups()
    if not float(lo) <= x <= float(hi) or (is_int and x != int(x)):
        raise BadInput("key %s: value '%s' out of range %s %s" % (name, value, k["range"], k["unit"]))
    return x


for _mode, _scenes in SCENES.items():     # the docstring's scene lists name keys and values of the table
    for _tab in _scenes.values():
        for _name, _value in _tab.items():
            check_value(KEYS[_mode], _name, _value)


def resolve(mode, seed, overrides):
    """Every key's value: overrides (validated), else the default, random ones drawn in table order."""
    keys = KEYS[mode]
    given = {}
    for name, value in overrides.items():
        if name not in keys:
            hint = cli_args.closest(name, list(keys))
            raise BadInput("unknown %s key '%s'%s" % (mode, name, " (did you mean '%s'?)" % hint if hint else ""))
        given[name] = check_value(keys, name, value)
    scene = SCENES[mode][given.get("scene", keys["scene"]["default"])] if mode in SCENES else {}
    rng, params, aux = stream(seed, mode, "geometry"), {}, {}
    for name, k in keys.items():
        d = scene.get(name, k["default"])
        m = re.fullmatch(r"(\+-)?U\[(\S+),(\S+)\]", d)
        if m:
            v = float(m.group(2)) + (float(m.group(3)) - float(m.group(2))) * rng.random()
            if m.group(1) and rng.random() < 0.5:
                v = -v
        elif d.startswith("U{"):
            opts = d[2:-1].split(",")
            v = check_value(keys, name, opts[int(rng.random() * len(opts))])
        elif d == "auto":
            v, aux[name] = None, rng.random()
        else:
            v = check_value(keys, name, d)
        params[name] = given.get(name, v)
    return params, aux


def stream(seed, mode, name):
    return random.Random("flightgen:%s:%d:%s" % (mode, seed, name))


# ---------------------------------------------------------------- noise
class Coloured:
    """Unit-variance coloured noise (gm or cascade, see the docstring) at non-decreasing times."""

    def __init__(self, kind, tau, rng):
        self.kind, self.tau, self.g, self.t = kind, tau, rng.gauss, None
        self.a = math.exp(-CASCADE_DT / (tau / 2)) if tau > 0 else 0.0

    def at(self, t):
        a, g = self.a, self.g
        if self.t is None:
            self.t, self.n = t, 0
            self.x = g(0.0, 1.0)
            self.f2 = (self.x + a * g(0.0, 1.0)) / (1 + a)
        elif self.kind == "gm":
            phi = math.exp(-(t - self.t) / self.tau)
            self.x, self.t = phi * self.x + math.sqrt(1 - phi * phi) * g(0.0, 1.0), t
        if self.kind == "gm":
            return self.x
        b = math.sqrt(1 - a * a)
        while self.n < round((t - self.t) / CASCADE_DT):
            self.x = a * self.x + b * g(0.0, 1.0)
            self.f2 = a * self.f2 + (1 - a) * self.x
            self.n += 1
        return self.f2 * (1 + a) / math.sqrt(1 + a * a)


def add_nav_error(rows, sigma, tau, white, rng):
    """rows (lat, lon, h, ecef) + per-axis local-ENU Gauss-Markov (sigma, tau) + white -> (lat, lon, h)."""
    phi = math.exp(-DT / tau)
    q = sigma * math.sqrt(1 - phi * phi)
    eps, out = [sigma * rng.gauss(0.0, 1.0) for _ in range(3)], []
    for k, (lat, lon, h, p) in enumerate(rows):
        if k:
            eps = [phi * x + q * rng.gauss(0.0, 1.0) for x in eps]
        d = [x + white * rng.gauss(0.0, 1.0) for x in eps]
        out.append(to_geodetic(*Frame(lat, lon, h).ecef(d)))
    return out


# ---------------------------------------------------------------- landing trajectory
def speed_fn(P):
    if P["geometry"] in ("straight", "level"):
        return lambda t: P["speed0_mps"]
    t0, d, v0, v1 = P["decel_start_s"], P["decel_s"], P["speed0_mps"], P["speed1_mps"]
    return lambda t: v0 if t <= t0 else v1 if t >= t0 + d else v0 + (v1 - v0) * (t - t0) / d


def plan(P, aux, radar_en):
    """Fill the auto keys; return the start state (e, n, psi) and the guidance function."""
    T, chi, g = P["duration_s"], P["heading_deg"], math.radians(P["glide_deg"])
    if P["decel_start_s"] is None:
        P["decel_start_s"] = T / 3 + aux["decel_start_s"] * T / 3
    speed, geo = speed_fn(P), P["geometry"]
    path = DT * sum(speed(k * DT) for k in range(int(round(T / DT))))
    a, w = math.radians(abs(P["intercept_deg"])), P["turn_rate_dps"]
    r = P["speed0_mps"] / math.radians(w)
    beta, n, hold = P["turn_deg"], int(P["n_turns"]), P["turn_hold_s"]
    holds = [hold * (1 if i in (0, n - 1) else 2) for i in range(n)]
    if P["start_x_m"] is None and geo != "level":
        extra = {"intercept": P["first_leg_m"] * (1 - math.cos(a)) + r * (a - math.sin(a)),
                 "turns": sum(holds) * P["speed0_mps"] * (1 - math.cos(math.radians(beta)))}.get(geo, 0.0)
        P["start_x_m"] = max(END_X_M + 100, END_X_M + path - extra)
    f, rt = axes(chi)
    x0, y0, psi0 = P["start_x_m"], 0.0, chi
    if geo == "intercept":
        y0 = math.copysign(P["first_leg_m"] * math.sin(a) + r * (1 - math.cos(a)), P["intercept_deg"])
        psi0 = chi - P["intercept_deg"]
    if geo == "level":
        bc = P["azimuth_reference_deg"] + P["pass_angle_deg"]
        psi0, d = bc + math.copysign(90.0, P["pass_dist_m"]), abs(P["pass_dist_m"])
        e0 = radar_en[0] + d * math.sin(math.radians(bc)) - T / 2 * P["speed0_mps"] * math.sin(math.radians(psi0))
        n0 = radar_en[1] + d * math.cos(math.radians(bc)) - T / 2 * P["speed0_mps"] * math.cos(math.radians(psi0))
    else:
        e0, n0 = -x0 * f[0] + y0 * rt[0], -x0 * f[1] + y0 * rt[1]
    t_s, offs = 0.2 * T, []
    for i, h in enumerate(holds):
        offs.append((t_s, t_s + h, beta * (-1) ** i))
        t_s += h
    phase = [0]

    def guide(t, s):
        e, nn, h, psi, v = s
        x, y = -(e * f[0] + nn * f[1]), e * rt[0] + nn * rt[1]
        pursuit = chi - math.degrees(math.atan(y / LOOKAHEAD_M))
        if geo == "level":
            return psi0, P["level_h_m"], 0.0, False
        if geo == "intercept":
            if phase[0] == 0 and abs(y) <= v / math.radians(w) * (1 - math.cos(math.radians(psi - chi))):
                phase[0] = 1
            if phase[0] == 1 and abs(wrap180(psi - chi)) < 1e-9:
                phase[0] = 2
            cmd = (psi0, chi, pursuit)[phase[0]]
        else:
            cmd = next((chi + o for t0, t1, o in offs if geo == "turns" and t0 <= t < t1), pursuit)
        glide = TCH_M + x * math.tan(g)
        ff = -math.tan(g) * v * math.cos(math.radians(psi - chi)) if glide < P["level_h_m"] else 0.0
        return cmd, min(P["level_h_m"], glide), ff, x <= END_X_M

    return (e0, n0, psi0), guide


def fly(start, guide, speed, P):
    """Integrate the kinematics (docstring) at DT; [(t, e, n, h)] until guide says done or duration_s."""
    e, n, psi = start
    v, w = speed(0.0), P["turn_rate_dps"]
    _, h, hdot, _ = guide(0.0, (e, n, 0.0, psi, v))
    out, k = [], 0
    while True:
        t = k * DT
        v = speed(t)
        cmd, h_cmd, ff, done = guide(t, (e, n, h, psi, v))
        out.append((t, e, n, h))
        if done or t >= P["duration_s"] - 1e-9:
            return out
        e, n = e + DT * v * math.sin(math.radians(psi)), n + DT * v * math.cos(math.radians(psi))
        h += DT * hdot
        psi += DT * max(-w, min(w, 10.0 * wrap180(cmd - psi)))
        hdot_cmd = max(-20.0, min(20.0, ff + 0.1 * (h_cmd - h)))
        hdot += max(-DT, min(DT, hdot_cmd - hdot))
        k += 1


# ---------------------------------------------------------------- measurement errors
def noise_sources(seed, mode, P, channels):
    white, outl = stream(seed, mode, "white"), stream(seed, mode, "outlier")
    col = {c: Coloured(P["coloured_kind"], P["coloured_tau_s"], stream(seed, mode, "coloured." + c)) for c in channels}

    def nu(t, c, sigma, sigma_c):
        """Noise of channel c at t: white + coloured; an outlier's is outlier_scale * sigma * w'."""
        w = white.gauss(0.0, 1.0)
        u = col[c].at(t) if P["coloured_tau_s"] > 0 else 0.0
        return sigma * w + sigma_c * u

    def outlier(sigmas):
        hit, ws = outl.random() < P["outlier_prob"], [outl.gauss(0.0, 1.0) for _ in sigmas]
        return [P["outlier_scale"] * s * x for s, x in zip(sigmas, ws)] if hit else None
    return nu, outlier


def radar_plots(P, seed, truth_ecef, radar, t_end):
    nu, outlier = noise_sources(seed, "landing", P, ("range", "azimuth", "elevation"))
    sig = (P["sigma_range_m"], P["sigma_az_deg"], P["sigma_el_deg"])
    bias = (P["range_bias_m"], P["az_bias_deg"], P["el_bias_deg"])
    drift = (P["range_drift_mps"], P["az_drift_degps"], P["el_drift_degps"])
    step = [P["step_size"] if c == P["step_channel"] else 0.0 for c in ("range", "azimuth", "elevation")]
    t_step = P["step_time_frac"] * t_end
    plots, k = [], 0
    while k / P["rate_hz"] <= t_end + 1e-9:
        t = k / P["rate_hz"]
        k += 1
        q = interp(truth_ecef, t - P["time_offset_s"])
        if q is None:
            continue
        rng_m, brg, el = polar(radar, q)
        az = wrap180(brg - P["azimuth_reference_deg"])
        if not (abs(az) < 60 and 0.1 <= el <= 30):
            continue
        er = math.radians(el)
        val = [(1 + P["range_gain"]) * rng_m, az + math.degrees(P["coupling_rad"] * math.tan(er)),
               el + math.degrees(P["refraction_rad"] / math.tan(er))]
        n = [nu(t, c, s, P["coloured_sigma_frac"] * s) for c, s in zip(("range", "azimuth", "elevation"), sig)]
        n = outlier(sig) or n
        m = [val[i] + bias[i] + drift[i] * t + (step[i] if t >= t_step else 0.0) + n[i] for i in range(3)]
        plots.append((t, m[0], wrap180(m[1]), m[2]))
    return plots


# Each file's columns: (unit, meaning), written beside it as NAME.units.json (one column per line,
# the project's format: {"column": {"unit": ..., "meaning": ...}}).
_GEO = {"t_s": ("s", "time since the flight's start"), "lat_deg": ("deg", "WGS84 latitude"),
        "lon_deg": ("deg", "WGS84 longitude"), "h_m": ("m", "height above the WGS84 ellipsoid")}
COLUMN_DOCS = {
    "radar.csv": {"t_s": ("s", "time stamp of the plot"), "range_m": ("m", "measured slant range from the radar"),
                  "azimuth_deg": ("deg", "measured azimuth from the azimuth reference, clockwise"),
                  "elevation_deg": ("deg", "measured elevation above the radar's horizontal")},
    "nav.csv": dict(_GEO, t_s=("s", "time of validity of the nav solution")),
    "truth.csv": dict(_GEO, t_s=("s", "time of the true position"), target=("", "target number")),
    "observer.csv": dict(_GEO, t_s=("s", "time of the observer's nav sample"),
                         heading_deg=("deg", "own ship's heading, clockwise from north")),
    "bearings.csv": {"t_s": ("s", "time stamp of the bearing"),
                     "bearing_deg": ("deg", "measured bearing from the observer, clockwise from north")},
    "detections.csv": {"t_s": ("s", "time stamp of the detection"), "sensor": ("", "sensor name"),
                       "range_m": ("m", "measured range from the sensor"),
                       "bearing_deg": ("deg", "measured bearing, clockwise from north")},
    "targets.csv": {"target": ("", "target number"), "length_m": ("m", "hull length as the target's AIS static data give it (A + B)"),
                    "beam_m": ("m", "hull beam as the AIS static data give it (C + D)"),
                    "to_bow_m": ("m", "AIS antenna's distance from the bow (A)"),
                    "to_port_m": ("m", "AIS antenna's distance from the port side (C)")},
}


def units_json(name, header):
    """The text of NAME.units.json for a CSV of these columns."""
    docs = COLUMN_DOCS[name]
    lines = [" %s: %s" % (json.dumps(c), json.dumps({"unit": docs[c][0], "meaning": docs[c][1]}))
             for c in header.split(",")]
    return "{\n" + ",\n".join(lines) + "\n}\n"


def save(outdir, tables, files=None):
    """Write (name, header, rows, printf format) tables into outdir (created if missing), each
    with NAME.units.json beside it; {name: path}."""
    if os.path.exists(outdir) and not os.path.isdir(outdir):
        raise BadInput("OUTDIR '%s' exists and is not a folder" % outdir)
    os.makedirs(outdir, exist_ok=True)
    files = files or {}
    for name, header, rows, fmt in tables:
        files[name] = os.path.join(outdir, name)
        with open(files[name], "w") as f:
            f.write(header + "\n")
            f.writelines(fmt % tuple(r) + "\n" for r in rows)
        with open(files[name][:-4] + ".units.json", "w") as f:
            f.write(units_json(name, header))
    return files


def axes(chi):
    """(along the runway, right of it) as (east, north) unit vectors for heading chi [deg]."""
    c = math.radians(chi)
    return (math.sin(c), math.cos(c)), (math.cos(c), -math.sin(c))


# ---------------------------------------------------------------- the two flights
def landing(outdir, seed=1, overrides=None, noise_seed=None):
    P, aux = resolve("landing", seed, dict(overrides or {}))
    save(outdir, ())
    chi = P["heading_deg"]
    P["azimuth_reference_deg"] = (chi + 180.0 + P["az_ref_offset_deg"]) % 360.0
    thr = Frame(P["lat_deg"], P["lon_deg"], P["threshold_h_m"])
    f, r = axes(chi)
    radar_en = [P["radar_along_m"] * f[i] + P["radar_lateral_m"] * r[i] for i in range(2)]
    rlat, rlon, rh, _ = thr.place(radar_en[0], radar_en[1], P["threshold_h_m"] + P["radar_height_m"])
    P.update(radar_lat_deg=rlat, radar_lon_deg=rlon, radar_h_m=rh)
    start, guide = plan(P, aux, radar_en)
    traj = fly(start, guide, speed_fn(P), P)
    rows = [thr.place(e, n, P["threshold_h_m"] + h) for _, e, n, h in traj]
    times = [s[0] for s in traj]
    truth = [(t,) + row[:3] for t, row in zip(times, rows)]
    navr = add_nav_error(rows, P["nav_sigma_m"], P["nav_tau_s"], P["nav_white_m"], stream(seed if noise_seed is None else noise_seed, "landing", "nav"))
    nav = [(t,) + tuple(row) for t, row in zip(times, navr)]
    plots = radar_plots(P, seed if noise_seed is None else noise_seed, [row[3] for row in rows], Frame(rlat, rlon, rh), times[-1])
    P.update(t_end_s=times[-1], n_plots=len(plots), step_time_s=P["step_time_frac"] * times[-1])
    site = {"radar": {"lat_deg": rlat, "lon_deg": rlon, "h_m": rh, "azimuth_reference_deg": P["azimuth_reference_deg"]},
            "runway": {"threshold_lat_deg": P["lat_deg"], "threshold_lon_deg": P["lon_deg"],
                       "threshold_h_m": P["threshold_h_m"], "heading_deg": chi}}
    files = save(outdir, (("radar.csv", "t_s,range_m,azimuth_deg,elevation_deg", plots, "%.6f,%.4f,%.8f,%.8f"),
                          ("nav.csv", "t_s,lat_deg,lon_deg,h_m", nav, "%.6f,%.9f,%.9f,%.4f"),
                          ("truth.csv", "t_s,lat_deg,lon_deg,h_m", truth, "%.6f,%.9f,%.9f,%.4f")))
    files["site.json"] = os.path.join(outdir, "site.json")
    with open(files["site.json"], "w") as fh:
        fh.write(json.dumps(site, indent=2) + "\n")
    return {"mode": "landing", "seed": seed, "params": P, "files": files, "truth": truth, "nav": nav, "plots": plots}


def observer_path(P):
    """Horizontal offset (e, n) of the observer from the path centre at time t."""
    R, L, geo = P["radius_m"], P["leg_m"], P["geometry"]
    per = {"orbit": 2 * math.pi * R, "racetrack": 2 * L + 2 * math.pi * R, "figure8": 4 * math.pi * R}[geo]
    sense = 1.0 if P["direction"] == "cw" else -1.0
    ax = math.radians(P["track_deg"])

    def at(t):
        s = (P["start_frac"] * per + sense * P["speed_mps"] * t) % per
        if geo == "orbit":
            return R * math.sin(s / R), R * math.cos(s / R)
        if geo == "racetrack":
            seg = [L, math.pi * R, L, math.pi * R]
            if s < seg[0]:
                a, b = -L / 2 + s, -R
            elif s < sum(seg[:2]):
                ph = (s - L) / R
                a, b = L / 2 + R * math.sin(ph), -R * math.cos(ph)
            elif s < sum(seg[:3]):
                a, b = L / 2 - (s - L - math.pi * R), R
            else:
                ph = (s - 2 * L - math.pi * R) / R
                a, b = -L / 2 - R * math.sin(ph), R * math.cos(ph)
        else:
            ph = s / R
            a, b = (R - R * math.cos(ph), R * math.sin(ph)) if ph < 2 * math.pi else (-R + R * math.cos(ph), R * math.sin(ph))
            b += R
        # a along the axis (bearing track_deg), b to its right
        return a * math.sin(ax) + b * math.cos(ax), a * math.cos(ax) - b * math.sin(ax)
    return at


def uav(outdir, seed=1, overrides=None, noise_seed=None):
    P, _ = resolve("uav", seed, dict(overrides or {}))
    save(outdir, ())
    site = Frame(P["lat_deg"], P["lon_deg"], 0.0)
    vb = (P["boat_speed_mps"] * math.sin(math.radians(P["boat_heading_deg"])),
          P["boat_speed_mps"] * math.cos(math.radians(P["boat_heading_deg"])))
    path, nk = observer_path(P), int(round(P["duration_s"] / DT)) + 1
    boat, obs = [], []
    for k in range(nk):
        t = k * DT
        c = (vb[0] * t, vb[1] * t) if P["centre"] == "follow" else (0.0, 0.0)
        o = path(t)
        boat.append(site.place(vb[0] * t, vb[1] * t, 0.0))
        obs.append(site.place(c[0] + o[0], c[1] + o[1], P["height_m"]))
    navr = add_nav_error(obs, P["obs_nav_sigma_m"], P["obs_nav_tau_s"], 0.0, stream(seed if noise_seed is None else noise_seed, "uav", "nav"))
    nu, outlier = noise_sources(seed if noise_seed is None else noise_seed, "uav", P, ("bearing",))
    b_ecef, o_ecef, t_end = [b[3] for b in boat], [o[3] for o in obs], (nk - 1) * DT
    bearings, k = [], 0
    while k / P["rate_hz"] <= t_end + 1e-9:
        t = k / P["rate_hz"]
        k += 1
        ob, bo = interp(o_ecef, t - P["time_offset_s"]), interp(b_ecef, t - P["time_offset_s"])
        if ob is None:
            continue
        _, brg, _ = polar(Frame(*to_geodetic(*ob)), bo)
        n = nu(t, "bearing", P["sigma_deg"], P["coloured_sigma_deg"])
        n = (outlier([P["sigma_deg"]]) or [n])[0]
        bearings.append((t, (brg + P["bias_deg"] + P["drift_degps"] * t + n) % 360.0))
    P.update(t_end_s=t_end, n_bearings=len(bearings))
    observer, truth = [(k * DT,) + tuple(r) for k, r in enumerate(navr)], [(k * DT, b[0], b[1]) for k, b in enumerate(boat)]
    files = save(outdir, (("observer.csv", "t_s,lat_deg,lon_deg,h_m", observer, "%.6f,%.9f,%.9f,%.4f"),
                          ("bearings.csv", "t_s,bearing_deg", bearings, "%.6f,%.8f"),
                          ("truth.csv", "t_s,lat_deg,lon_deg", truth, "%.6f,%.9f,%.9f")))
    return {"mode": "uav", "seed": seed, "params": P, "files": files, "truth": truth, "observer": observer,
            "observer_truth": [(k * DT,) + o[:3] for k, o in enumerate(obs)], "bearings": bearings}


# ---------------------------------------------------------------- ship radar
class Track:
    """Constant speed, legs of constant course joined by constant-rate turns, in a flat (e, n) plane;
    exact at any t (docstring). turns: [(start time, course change deg, rate deg/s > 0)] in time order;
    a turn starting before the previous one ends waits for it."""

    def __init__(self, e, n, course, speed, turns=()):
        self.v, self.segs, t = speed, [], 0.0
        for t_turn, change, rate in turns:
            t_turn = max(t_turn, t)
            self.segs.append((t, e, n, course, 0.0))
            e, n, course = self._advance(self.segs[-1], t_turn)
            w = math.copysign(rate, change)
            self.segs.append((t_turn, e, n, course, w))
            t = t_turn + abs(change) / rate
            e, n, course = self._advance(self.segs[-1], t)
        self.segs.append((t, e, n, course, 0.0))
        self.starts = [sg[0] for sg in self.segs]

    def _advance(self, seg, t):
        t0, e, n, c, w = seg
        tau = t - t0
        if w == 0.0:
            cr = math.radians(c)
            return e + self.v * tau * math.sin(cr), n + self.v * tau * math.cos(cr), c
        c1 = c + w * tau
        k = self.v / math.radians(w)
        a0, a1 = math.radians(c), math.radians(c1)
        return e + k * (math.cos(a0) - math.cos(a1)), n + k * (math.sin(a1) - math.sin(a0)), c1

    def at(self, t):
        """(e, n, course deg) at t (before the first segment: its leg extended backwards)."""
        i = max(0, bisect.bisect_right(self.starts, t) - 1)
        return self._advance(self.segs[i], t)


def wrap360(a, digits):
    """a in [0, 360), also after rounding to digits decimals (no '360.000')."""
    a %= 360.0
    return 0.0 if round(a, digits) >= 360.0 else a


def poisson(rng, lam):
    """Poisson(lam) draw (Knuth; lam <= 100)."""
    if lam <= 0:
        return 0
    lim, k, p = math.exp(-lam), 0, rng.random()
    while p > lim:
        k += 1
        p *= rng.random()
    return k


def _ship_draws(P, seed, i):
    """Ship i's drawn values from its geometry streams target.i, hull.i, moor.i, sigma.i and
    ais_static.i (docstring); every stream drawn whatever the keys."""
    g = stream(seed, "shipradar", "target.%d" % i)
    s = {"id": i, "u": [g.random() for _ in range(9)], "L": 0.0, "B": 0.0, "A": 0.0, "C": 0.0}
    if P["hull_max_length_m"] > 0:
        h = stream(seed, "shipradar", "hull.%d" % i)
        u = [h.random() for _ in range(4)]
        lo, hi = P["hull_min_length_m"], P["hull_max_length_m"]
        L = lo * (hi / lo) ** u[0]
        B = max(3.0, L * (0.12 + 0.08 * u[1]))
        s.update(L=L, B=B, A=(0.15 + 0.7 * u[2]) * L, C=(0.2 + 0.6 * u[3]) * B)
    m = stream(seed, "shipradar", "moor.%d" % i)
    um, us, ug = m.random(), m.random(), m.random()
    cmax = int(P["cluster_max"])
    s.update(moored=um < P["moored_fraction"], size=1 if cmax < 2 else 2 + int(us * (cmax - 1)), gap=1.0 + 2.0 * ug)
    q = stream(seed, "shipradar", "sigma.%d" % i)
    ub, ur = q.random(), q.random()
    s.update(sig_b=P["bearing_sigma_deg"] + (P["bearing_sigma_max_deg"] - P["bearing_sigma_deg"]) * ub,
             sig_r=P["range_sigma_m"] + (P["range_sigma_max_m"] - P["range_sigma_m"]) * ur)
    a = stream(seed, "shipradar", "ais_static.%d" % i)
    u = [a.random() for _ in range(4)]
    s.update(silent=u[0] < P["ais_silent_fraction"], wrong=u[1] < P["ais_wrong_dims_fraction"],
             f=(0.3 + 2.7 * u[2], 0.3 + 2.7 * u[3]))
    return s


def _groups(ships):
    """Placement groups in id order: a moving ship alone, moored ships filling clusters (docstring)."""
    groups, cur = [], None
    for s in ships:
        if not s["moored"]:
            s["cluster"] = None
            groups.append([s])
            continue
        if cur is None or len(cur) >= cur[0]["size"]:
            cur = [s]
            groups.append(cur)
        else:
            cur.append(s)
        s["cluster"] = cur[0]["id"]
    return groups


def _layout(group, p, course):
    """[(antenna (e, n), hull centre (e, n), half diagonal)] of a group's ships at t_p, the first
    one's antenna at p, all on the plane course `course`, each next alongside to starboard."""
    c = math.radians(course)
    f, sb = (math.sin(c), math.cos(c)), (math.cos(c), -math.sin(c))
    out, centre = [], None
    for j, s in enumerate(group):
        ahead, right = s["A"] - s["L"] / 2, s["B"] / 2 - s["C"]     # hull centre from the antenna
        if j == 0:
            ant = p
            centre = (p[0] + ahead * f[0] + right * sb[0], p[1] + ahead * f[1] + right * sb[1])
        else:
            d = (group[j - 1]["B"] + s["B"]) / 2 + s["gap"]
            centre = (centre[0] + d * sb[0], centre[1] + d * sb[1])
            ant = (centre[0] - ahead * f[0] - right * sb[0], centre[1] - ahead * f[1] - right * sb[1])
        out.append((ant, centre, math.hypot(s["L"], s["B"]) / 2))
    return out


def _misplaced(lay, placed, shore, hulls):
    """'land', 'overlap' or None for a group's layout against the shore and the hulls placed before."""
    for _, c, R in lay:
        if shore and c[0] * shore[0] + c[1] * shore[1] + R + 10.0 > shore[2]:
            return "land"
    for _, c, R in lay:
        if hulls and any(math.hypot(c[0] - c2[0], c[1] - c2[1]) < R + R2 for c2, R2 in placed):
            return "overlap"
    return None


def _shore(P):
    """(unit normal e, n from the own start towards the shore, its distance) or None without land."""
    if int(P["land_points"]) == 0:
        return None
    lb = math.radians(P["land_bearing_deg"])
    return math.sin(lb), math.cos(lb), P["land_distance_m"]


def _ais_static(P, s):
    """The whole-metre (length, beam, to bow, to port) the ship's AIS sends (docstring), or None."""
    if P["hull_max_length_m"] <= 0 or s["silent"]:
        return None
    L, B, A, C = s["L"], s["B"], s["A"], s["C"]
    if s["wrong"]:
        L2, B2 = min(1000.0, s["f"][0] * L), s["f"][1] * B
        L, B, A, C = L2, B2, A * L2 / L, C * B2 / B
    return tuple(int(math.floor(x + 0.5)) for x in (L, B, A, C))


def ship_targets(P, seed, obs):
    """[(Track, (de, dn) offset, info)] for targets 1..n_targets in id order (docstring: targets,
    hulls, moored clusters, placement)."""
    T, tp = P["duration_s"], P["place_time_frac"] * P["duration_s"]
    oe, on, _ = obs.at(tp)
    ships = [_ship_draws(P, seed, i) for i in range(1, int(P["n_targets"]) + 1)]
    shore, hulls = _shore(P), P["hull_max_length_m"] > 0
    span = P["target_max_range_m"] - P["target_min_range_m"]
    placed, out = [], {}
    for grp in _groups(ships):
        s0, redraw = grp[0], None
        u, moored = s0["u"], s0["moored"]
        dist = P["target_min_range_m"] + (P["target_max_range_m"] - P["target_min_range_m"]) * u[0]
        brg, course = 360.0 * u[1], 360.0 * u[3]
        speed = 0.0 if moored else P["target_min_speed_mps"] + (P["target_max_speed_mps"] - P["target_min_speed_mps"]) * u[2]
        turn = None
        if not moored and u[4] < P["turn_fraction"]:
            turn = ((0.1 + 0.7 * u[5]) * T, math.copysign(20.0 + 70.0 * u[6], u[7] - 0.5), 0.1 + 0.4 * u[8])
        tr = Track(0.0, 0.0, course, speed, [turn] if turn else [])
        e, n, c_tp = tr.at(tp)
        mirrored = False
        for attempt in range(50 if shore or hulls else 1):
            if attempt:
                redraw = redraw or stream(seed, "shipradar", "place.%d" % s0["id"])
                dist, brg = P["target_min_range_m"] + span * redraw.random(), 360.0 * redraw.random()
            p = (oe + dist * math.sin(math.radians(brg)), on + dist * math.cos(math.radians(brg)))
            if not (shore or hulls):
                break
            why = _misplaced(_layout(grp, p, c_tp), placed, shore, hulls)
            mirrored = why == "land"
            if mirrored:            # mirrored across the line through the own ship along the shore
                brg = (2.0 * P["land_bearing_deg"] + 180.0 - brg) % 360.0
                p = (oe + dist * math.sin(math.radians(brg)), on + dist * math.cos(math.radians(brg)))
                why = _misplaced(_layout(grp, p, c_tp), placed, shore, hulls)
            if why is None:
                break
        for j, (s, (ant, centre, R)) in enumerate(zip(grp, _layout(grp, p, c_tp))):
            placed.append((centre, R))
            if j == 0:
                tr_s, off = tr, (p[0] - e, p[1] - n)
                rng_b = (dist, brg)
            else:
                tr_s, off = Track(0.0, 0.0, course, 0.0), ant
                rng_b = (math.hypot(ant[0] - oe, ant[1] - on), math.degrees(math.atan2(ant[0] - oe, ant[1] - on)) % 360.0)
            first = j == 0 and turn is not None
            info = {"id": s["id"], "speed_mps": speed if j == 0 else 0.0, "course_deg": course,
                    "place_range_m": rng_b[0], "place_bearing_deg": rng_b[1],
                    "turn_start_s": turn[0] if first else None, "turn_deg": turn[1] if first else None,
                    "turn_rate_dps": turn[2] if first else None,
                    "length_m": s["L"], "beam_m": s["B"], "to_bow_m": s["A"], "to_port_m": s["C"],
                    "moored": s["moored"], "cluster": s["cluster"], "silent": s["silent"],
                    "wrong_dims": s["wrong"] and _ais_static(P, s) is not None, "ais_static": _ais_static(P, s),
                    "bearing_sigma_deg": s["sig_b"], "range_sigma_m": s["sig_r"], "place_attempts": attempt + 1,
                    "place_mirrored": mirrored}
            out[s["id"]] = (tr_s, off, info)
    return [out[i] for i in sorted(out)]


def illuminations(look, P, t_end):
    """Every t in [0, t_end) with theta(t) = beta(t) (mod 360) for one target (docstring), as
    [(t, r, beta)]; look(t) = (r, beta). Returns (rows, unresolved count)."""
    per, b0 = P["scan_period_s"], P["scan_start_bearing_deg"]
    om = 360.0 / per
    theta = lambda t: b0 + (t % per) * om
    out, bad = [], 0
    t = ((look(0.0)[1] - b0) % 360.0) / om
    last, step = None, per
    while t < t_end + per:
        guess = t
        for _ in range(60):
            r, b = look(t)
            d = wrap180(b - theta(t)) / om
            if abs(d) < 1e-7:
                break
            t += d
        else:
            d = None
        if d is None or (last is not None and t <= last + 0.25 * per):
            bad += d is None
            t = guess + per
            continue
        if t >= t_end:
            break
        if t >= 0.0:
            out.append((t, r, b))
        if last is not None:
            step = min(1.5 * per, max(0.5 * per, t - last))
        last, t = t, t + step
    return out, bad


class Hull:
    """A ship's hull rectangle about its AIS antenna and its echo's range and bearing (docstring)."""

    def __init__(self, info, site):
        L, B, A, C = info["length_m"], info["beam_m"], info["to_bow_m"], info["to_port_m"]
        self.x, self.y, self.site = (A, A - L), (-C, B - C), site
        self.centre = (A - L / 2, B / 2 - C)

    def axes(self, lat, lon, course):
        """(forward, starboard) ECEF unit vectors and the true heading [deg] at (lat, lon) of the
        plane course `course` (its direction projected on the tangent plane there)."""
        la, lo = math.radians(lat), math.radians(lon)
        east = (-math.sin(lo), math.cos(lo), 0.0)
        north = (-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la))
        c, m = math.radians(course), self.site.m
        v = [math.sin(c) * m[0][k] + math.cos(c) * m[1][k] for k in range(3)]
        fe, fn = sum(v[k] * east[k] for k in range(3)), sum(v[k] * north[k] for k in range(3))
        h = math.hypot(fe, fn)
        fe, fn = fe / h, fn / h
        return ([fe * east[k] + fn * north[k] for k in range(3)], [fn * east[k] - fe * north[k] for k in range(3)],
                math.degrees(math.atan2(fe, fn)) % 360.0)

    def echo(self, radar, p, fwd, stb):
        """(r, beta) of the hull's echo from radar (Frame), the antenna at ECEF p, axes fwd and stb."""
        m = radar.m
        q = radar.enu(p)
        f = [m[i][0] * fwd[0] + m[i][1] * fwd[1] + m[i][2] * fwd[2] for i in range(3)]
        s = [m[i][0] * stb[0] + m[i][1] * stb[1] + m[i][2] * stb[2] for i in range(3)]

        def pt(x, y):
            return [q[i] + x * f[i] + y * s[i] for i in range(3)]
        q0 = pt(self.x[0], self.y[0])
        a = [(self.y[1] - self.y[0]) * s[i] for i in range(3)]
        b = [(self.x[1] - self.x[0]) * f[i] for i in range(3)]
        s0 = -sum(q0[i] * a[i] for i in range(3)) / sum(x * x for x in a)
        t0 = -sum(q0[i] * b[i] for i in range(3)) / sum(x * x for x in b)
        sc, tc = min(1.0, max(0.0, s0)), min(1.0, max(0.0, t0))
        r = math.sqrt(sum((q0[i] + sc * a[i] + tc * b[i]) ** 2 for i in range(3)))
        cen = pt(*self.centre)
        bc = math.degrees(math.atan2(cen[0], cen[1]))
        if 0.0 <= s0 <= 1.0 and 0.0 <= t0 <= 1.0:      # the radar over the hull
            return r, bc
        d = [wrap180(math.degrees(math.atan2(c[0], c[1])) - bc) for c in (pt(x, y) for x in self.x for y in self.y)]
        return r, bc + (min(d) + max(d)) / 2


def ship_look(P, site, antenna, tr, off, info):
    """look(t) = (r, beta) of one target's echo from the radar antenna at t (docstring)."""
    if info["length_m"] <= 0:
        def look(t):
            fr, _ = antenna(t)
            e, n, _ = tr.at(t)
            r, b, _ = polar(fr, site.place(e + off[0], n + off[1], 0.0)[3])
            return r, b
        return look
    hull = Hull(info, site)
    e, n, c = tr.at(P["place_time_frac"] * P["duration_s"])
    lat, lon, _, p = site.place(e + off[0], n + off[1], 0.0)
    fixed = (p,) + tuple(hull.axes(lat, lon, c)[:2]) if info["speed_mps"] == 0 and info["turn_deg"] is None else None

    def look_hull(t):
        fr, _ = antenna(t)
        if fixed:
            return hull.echo(fr, *fixed)
        e, n, c = tr.at(t)
        lat, lon, _, p = site.place(e + off[0], n + off[1], 0.0)
        fwd, stb, _ = hull.axes(lat, lon, c)
        return hull.echo(fr, p, fwd, stb)
    return look_hull


def unresolved(echoes, res, bw):
    """Echoes (k, t, id, r, beta, ...) in groups: linked within one scan k when closer than res in r
    and bw in beta (single linkage); the groups in the order of their first echo, each in order."""
    if not (res > 0 and bw > 0):
        return [[x] for x in echoes]
    parent = list(range(len(echoes)))

    def root(j):
        while parent[j] != j:
            parent[j] = parent[parent[j]]
            j = parent[j]
        return j
    scans = {}
    for j, x in enumerate(echoes):
        scans.setdefault(x[0], []).append(j)
    for idx in scans.values():
        idx.sort(key=lambda j: echoes[j][3])
        for a, ja in enumerate(idx):
            for jb in idx[a + 1:]:
                if echoes[jb][3] - echoes[ja][3] >= res:
                    break
                if abs(wrap180(echoes[jb][4] - echoes[ja][4])) < bw:
                    parent[root(jb)] = root(ja)
    groups = {}
    for j, x in enumerate(echoes):
        groups.setdefault(root(j), []).append(x)
    return list(groups.values())


def merged(group):
    """(k, t, r, beta, x_r, x_b) of a group of echoes (k, t, id, r, beta, x_r, x_b, weight, ...):
    the echo itself, or the weighted means (bearings about the first's)."""
    if len(group) == 1:
        return group[0][:2] + group[0][3:7]
    W = sum(x[7] for x in group)
    mean = lambda j: sum(x[7] * x[j] for x in group) / W
    b1 = group[0][4]
    return (group[0][0], mean(1), mean(3), b1 + sum(x[7] * wrap180(x[4] - b1) for x in group) / W, mean(5), mean(6))


def sea_clutter(P, ns, n_scans):
    """[(k, true range, true bearing)] of the sea clutter (docstring; stream sea_clutter)."""
    g, out = stream(ns, "shipradar", "sea_clutter"), []
    r0, s = P["min_range_m"], P["sea_clutter_scale_m"]
    cdf = 1.0 - math.exp(-(P["max_range_m"] - r0) / s)
    for k in range(n_scans):
        for _ in range(poisson(g, P["sea_clutter_per_scan"])):
            r = r0 - s * math.log(1.0 - g.random() * cdf)
            out.append((k, r, 360.0 * g.random()))
    return out


def land_reflectors(P, seed, site):
    """[(lat, lon, ECEF)] of the shore's reflectors (docstring; stream land_points), [] without land."""
    shore = _shore(P)
    if shore is None:
        return []
    g, (ne, nn, D), H = stream(seed, "shipradar", "land_points"), shore, P["land_half_length_m"]
    out = []
    for _ in range(int(P["land_points"])):
        a = H * (2.0 * g.random() - 1.0)
        lat, lon, _, p = site.place(D * ne + a * nn, D * nn - a * ne, 0.0)
        out.append((lat, lon, p))
    return out


def _fast_polar(fr, p):
    """(slant range, bearing deg) of ECEF p from Frame fr."""
    o, m = fr.o, fr.m
    dx, dy, dz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
    e = m[0][0] * dx + m[0][1] * dy
    n = m[1][0] * dx + m[1][1] * dy + m[1][2] * dz
    u = m[2][0] * dx + m[2][1] * dy + m[2][2] * dz
    return math.sqrt(e * e + n * n + u * u), math.degrees(math.atan2(e, n))


def land_echoes(P, ns, refl, antenna, n_scans):
    """[(k, t, j, r, beta, w_r, w_b)] of every land reflector j lit in scan k and detected
    (docstring: quadratic in t through the scan's start, middle and end; stream land.j)."""
    if not refl:
        return []
    per, b0 = P["scan_period_s"], P["scan_start_bearing_deg"]
    om = 360.0 / per
    frames = [antenna(h * per / 2)[0] for h in range(2 * n_scans + 1)]
    out = []
    for j, (_, _, p) in enumerate(refl):
        g = stream(ns, "shipradar", "land.%d" % (j + 1))
        prev = _fast_polar(frames[0], p)
        for k in range(n_scans):
            ud, wr, wb = g.random(), g.gauss(0.0, 1.0), g.gauss(0.0, 1.0)
            (r0, bb0), (rm, bm), (r1, bb1) = prev, _fast_polar(frames[2 * k + 1], p), _fast_polar(frames[2 * k + 2], p)
            prev = (r1, bb1)
            if ud >= P["land_p_detect"] or min(r0, r1) > P["max_range_m"] + 100.0:
                continue
            bm, bb1 = bb0 + wrap180(bm - bb0), bb0 + wrap180(bb1 - bb0)
            c2 = 2.0 * (bb1 - bb0 - 2.0 * (bm - bb0)) / per ** 2
            c1 = (bb1 - bb0) / per - c2 * per
            d2 = 2.0 * (r1 - r0 - 2.0 * (rm - r0)) / per ** 2
            d1 = (r1 - r0) / per - d2 * per
            tau = ((bb0 - b0) % 360.0) / om
            for _ in range(20):
                step = wrap180(bb0 + c1 * tau + c2 * tau * tau - b0 - om * tau) / (om - c1 - 2.0 * c2 * tau)
                tau += step
                if abs(step) < 1e-9:
                    break
            r = r0 + d1 * tau + d2 * tau * tau
            if 0.0 <= tau < per and P["min_range_m"] <= r <= P["max_range_m"]:
                out.append((k, k * per + tau, j + 1, r, bb0 + c1 * tau + c2 * tau * tau, wr, wb))
    return out


def _ship_keys(P):
    """The auto keys derived and the pairs of keys checked (BadInput naming both)."""
    for key, base in (("bearing_sigma_max_deg", "bearing_sigma_deg"), ("range_sigma_max_m", "range_sigma_m")):
        if P[key] is None:
            P[key] = P[base]
    if P["land_bearing_deg"] is None:
        P["land_bearing_deg"] = (P["obs_course_deg"] - math.copysign(90.0, P["obs_turn_deg"])) % 360.0
    pairs = [("target_min_range_m", "target_max_range_m"), ("target_min_speed_mps", "target_max_speed_mps"),
             ("ais_min_s", "ais_max_s"), ("min_range_m", "max_range_m"),
             ("bearing_sigma_deg", "bearing_sigma_max_deg"), ("range_sigma_m", "range_sigma_max_m")]
    if P["hull_max_length_m"] > 0:
        pairs.append(("hull_min_length_m", "hull_max_length_m"))
    for lo, hi in pairs:
        if P[lo] > P[hi]:
            raise BadInput("key %s (%g) must not exceed %s (%g)" % (lo, P[lo], hi, P[hi]))


def ais_reports(P, seed, ns, site, targets):
    """truth.csv rows (t, id, lat, lon) of the ships with AIS (docstring)."""
    T, whole, truth = P["duration_s"], P["ais_whole_seconds"] == 1, []
    span = P["ais_max_s"] - P["ais_min_s"]
    for tr, off, info in targets:
        i = info["id"]
        if info["silent"]:
            continue
        ts_rng, nz = stream(seed, "shipradar", "ais_times.%d" % i), stream(ns, "shipradar", "ais_noise.%d" % i)
        t = ts_rng.random() * (P["ais_min_s"] + span * ts_rng.random())
        if whole:
            t = float(math.ceil(t))
        while t <= T + 1e-9:
            e, n, _ = tr.at(t - P["ais_time_offset_s"])
            we, wn = nz.gauss(0.0, 1.0), nz.gauss(0.0, 1.0)
            lat, lon, _, _ = site.place(e + off[0] + P["ais_sigma_m"] * we, n + off[1] + P["ais_sigma_m"] * wn, 0.0)
            truth.append((t, i, lat, lon))
            d = P["ais_min_s"] + span * ts_rng.random()
            t += max(1.0, math.floor(d + 0.5)) if whole else d
    truth.sort(key=lambda r: (r[0], r[1]))
    return truth


def ship_echoes(P, ns, site, antenna, targets, n_scans, t_end):
    """(detected echoes (k, t, id, r, beta, x_r, x_b, weight, lit index), illuminations [t, id, k, r,
    beta, detected], failed illumination solves): each ship's illuminations and noise (docstring)."""
    per, tau = P["scan_period_s"], P["noise_tau_s"]
    echoes, lit, n_bad = [], [], 0
    for tr, off, info in targets:
        i = info["id"]
        rows, bad = illuminations(ship_look(P, site, antenna, tr, off, info), P, t_end)
        n_bad += bad
        det, white = stream(ns, "shipradar", "detect.%d" % i), stream(ns, "shipradar", "white.%d" % i)
        sr, sb, w = info["range_sigma_m"], info["bearing_sigma_deg"], info["length_m"] or 1.0
        t_prev = xr = xb = None
        for t, r, b in rows:
            ud, wr, wb = det.random(), white.gauss(0.0, 1.0), white.gauss(0.0, 1.0)
            if tau > 0 and t_prev is not None:
                phi = math.exp(-(t - t_prev) / tau)
                q = math.sqrt(1.0 - phi * phi)
                xr, xb = phi * xr + q * sr * wr, phi * xb + q * sb * wb
            else:
                xr, xb = sr * wr, sb * wb
            t_prev = t
            k = min(n_scans - 1, int(math.floor(t / per)))
            lit.append([t, i, k, r, b % 360.0, False])
            if P["min_range_m"] <= r <= P["max_range_m"] and ud < P["p_detect"]:
                echoes.append((k, t, i, r, b, xr, xb, w, len(lit) - 1))
    return echoes, lit, n_bad


def shipradar(outdir, seed=1, overrides=None, noise_seed=None):
    P, _ = resolve("shipradar", seed, dict(overrides or {}))
    _ship_keys(P)
    save(outdir, ())
    ns = seed if noise_seed is None else noise_seed
    T, per, hant = P["duration_s"], P["scan_period_s"], P["antenna_h_m"]
    om, b0 = 360.0 / per, P["scan_start_bearing_deg"]
    site = Frame(P["lat_deg"], P["lon_deg"], 0.0)
    nt = int(P["obs_turns"])
    obs = Track(0.0, 0.0, P["obs_course_deg"], P["obs_speed_mps"],
                [((k + 1) * T / (nt + 1), P["obs_turn_deg"] * (-1) ** k, P["obs_turn_rate_dps"]) for k in range(nt)])
    targets = ship_targets(P, seed, obs)
    tp = P["place_time_frac"] * T
    for tr, off, info in targets:     # the true heading at t_p (the hull's; a moored ship's for good)
        e, n, c = tr.at(tp)
        lat, lon, _, _ = site.place(e + off[0], n + off[1], 0.0)
        info["heading_deg"] = Hull(info, site).axes(lat, lon, c)[2]
    observer = []
    for k in range(int(math.floor(T + 1e-9)) + 1):
        e, n, c = obs.at(float(k))
        lat, lon, h, _ = site.place(e, n, hant)
        observer.append((float(k), lat, lon, h, wrap360(c, 4)))

    def antenna(t):
        e, n, _ = obs.at(t)
        lat, lon, h, p = site.place(e, n, hant)
        return Frame(lat, lon, h), p

    n_scans = int(math.floor(T / per + 1e-9))
    t_end = n_scans * per
    stamp = lambda t, k: (t if P["stamp"] == "illumination" else (k + 1) * per) + P["time_offset_s"]
    echoes, lit, n_bad = ship_echoes(P, ns, site, antenna, targets, n_scans, t_end)
    dets, src, n_merges, n_merged = [], [], 0, 0
    for grp in unresolved(echoes, P["range_resolution_m"], P["beamwidth_deg"]):
        k, t, r, b, xr, xb = merged(grp)
        rm = (1 + P["range_gain"]) * r + P["range_bias_m"] + xr
        bm = wrap360(b + P["bearing_bias_deg"] + xb, 8)
        n_merges, n_merged = n_merges + (len(grp) > 1), n_merged + (len(grp) if len(grp) > 1 else 0)
        if rm > 0:
            dets.append((stamp(t, k), "radar", rm, bm))
            src.append(("ship", tuple(sorted(x[2] for x in grp))))
            for x in grp:
                lit[x[8]][5] = True
    n_target_dets = len(dets)
    clut = stream(ns, "shipradar", "clutter")
    rmin = max(P["min_range_m"], 1.0)
    for k in range(n_scans):
        for _ in range(poisson(clut, P["clutter_per_scan"])):
            rm = rmin + (P["max_range_m"] - rmin) * clut.random()
            bm = wrap360(360.0 * clut.random(), 8)
            t = k * per + ((bm - b0) % 360.0) / om
            dets.append(((t if P["stamp"] == "illumination" else (k + 1) * per) + P["time_offset_s"], "radar", rm, bm))
            src.append(("clutter",))
    n_clutter = len(dets) - n_target_dets
    for k, r, b in sea_clutter(P, ns, n_scans):
        rm = (1 + P["range_gain"]) * r + P["range_bias_m"]
        if rm > 0:
            dets.append((stamp(k * per + ((b - b0) % 360.0) / om, k), "radar", rm, wrap360(b + P["bearing_bias_deg"], 8)))
            src.append(("sea",))
    n_sea = len(dets) - n_target_dets - n_clutter
    refl = land_reflectors(P, seed, site)
    for k, t, j, r, b, wr, wb in land_echoes(P, ns, refl, antenna, n_scans):
        rm = (1 + P["range_gain"]) * r + P["range_bias_m"] + P["range_sigma_m"] * wr
        if rm > 0:
            dets.append((stamp(t, k), "radar", rm, wrap360(b + P["bearing_bias_deg"] + P["bearing_sigma_deg"] * wb, 8)))
            src.append(("land", j))
    order = sorted(range(len(dets)), key=lambda j: (dets[j][0], dets[j][3], dets[j][2]))
    dets, src = [dets[j] for j in order], [src[j] for j in order]
    lit = sorted(tuple(x) for x in lit)
    truth = ais_reports(P, seed, ns, site, targets)
    infos = [t[2] for t in targets]
    P.update(omega_dps=om, n_scans=n_scans, n_illuminations=len(lit), n_detections=len(dets),
             n_target_detections=n_target_dets, n_clutter=n_clutter, n_truth_rows=len(truth),
             n_unresolved=n_bad, n_sea_clutter=n_sea, n_land=len(dets) - n_target_dets - n_clutter - n_sea,
             n_land_reflectors=len(refl), n_unresolved_merges=n_merges, n_merged_echoes=n_merged,
             n_moored=sum(x["moored"] for x in infos), n_clusters=len({x["cluster"] for x in infos if x["moored"]}),
             n_silent=sum(x["silent"] for x in infos), n_wrong_dims=sum(x["wrong_dims"] for x in infos),
             n_replaced=sum(x["place_attempts"] > 1 for x in infos), n_mirrored=sum(x["place_mirrored"] for x in infos))
    tables = [("observer.csv", "t_s,lat_deg,lon_deg,h_m,heading_deg", observer, "%.6f,%.9f,%.9f,%.4f,%.4f"),
              ("detections.csv", "t_s,sensor,range_m,bearing_deg", dets, "%.6f,%s,%.4f,%.8f"),
              ("truth.csv", "t_s,target,lat_deg,lon_deg", truth, "%.6f,%d,%.9f,%.9f")]
    if P["hull_max_length_m"] > 0:
        tables.append(("targets.csv", "target,length_m,beam_m,to_bow_m,to_port_m",
                       [(x["id"],) + x["ais_static"] for x in infos if x["ais_static"]], "%d,%d,%d,%d,%d"))
    files = save(outdir, tables)
    return {"mode": "shipradar", "seed": seed, "params": P, "files": files, "truth": truth, "observer": observer,
            "detections": dets, "sources": src, "illuminations": lit, "targets": infos,
            "land": [(lat, lon) for lat, lon, _ in refl]}


# ---------------------------------------------------------------- command line
def main(argv):
    ap = cli_args.ArgumentParser(PROG, __doc__)
    ap.add_argument("mode", metavar="MODE", nargs="?", default=None, help="landing, uav or shipradar")
    ap.add_argument("outdir", metavar="OUTDIR", nargs="?", help="output folder (created if missing; its files replaced)")
    ap.add_argument("--seed", metavar="N", default="1", help="random seed, an integer >= 0")
    ap.add_argument("--noise-seed", metavar="N", default=None,
                    help="seed of the noise streams (nav, white, outlier, coloured) alone, an integer >= 0; "
                         "default: --seed (the geometry then stays that of --seed)")
    ap.add_argument("--set", metavar="KEY=VALUE", action="append", help="set a key (see --list-keys); repeatable")
    ap.add_argument("--list-keys", action="store_true", help="print every key of MODE with default, range, unit; exit")
    args = ap.parse_args(argv)
    if args.mode is None:  # both missing named at once (--list-keys needs no OUTDIR)
        ap.error("MODE (landing, uav or shipradar)%s required (see %s --help)"
                 % (" and OUTDIR are" if not args.outdir and not args.list_keys else " is", PROG))
    if args.mode not in KEYS:
        hint = cli_args.closest(args.mode, list(KEYS))
        ap.error("unknown mode '%s'%s: give landing, uav or shipradar" % (args.mode, " (did you mean '%s'?)" % hint if hint else ""))
    if args.list_keys:
        scenes = SCENES.get(args.mode, {})
        print("\n".join(k["line"] + "".join("  (%s: %s)" % (sc, tab[name]) for sc, tab in scenes.items() if name in tab)
                        for name, k in KEYS[args.mode].items()))
        return 0
    if not args.outdir:
        ap.error("OUTDIR is required (see %s --help)" % PROG)
    if not re.fullmatch(r"\d+", args.seed):
        ap.error("--seed must be an integer >= 0, got '%s'" % args.seed)
    if args.noise_seed is not None and not re.fullmatch(r"\d+", args.noise_seed):
        ap.error("--noise-seed must be an integer >= 0, got '%s'" % args.noise_seed)
    noise_seed = None if args.noise_seed is None else int(args.noise_seed)
    overrides = {}
    for item in args.set or []:
        if "=" not in item:
            ap.error("--set '%s': expected KEY=VALUE" % item)
        key, value = item.split("=", 1)
        if key in overrides:
            ap.error("--set: key %s given twice" % key)
        overrides[key] = value
    try:
        res = {"landing": landing, "uav": uav, "shipradar": shipradar}[args.mode](args.outdir, int(args.seed), overrides, noise_seed)
    except BadInput as e:
        ap.error(str(e))
    print(json.dumps(res["params"], indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
