# Pedestrian trajectories (the ETH and UCY files: CSV frame,id,x,y in metres), each person a
# track of timed ground points, sampled with linear interpolation. Time: the most common
# step between a person's frame numbers is one sample at 2.5 Hz, as in the crowdgaze CLI.
extends Reference

const SAMPLE_RATE = 2.5

var tracks = {}       # id -> {"times": [], "points": [Vector2]}
var first_time = INF
var last_time = -INF


# Reads a trajectory file; returns an error string, or "" on success.
func load_csv(path):
	var file = File.new()
	if file.open(path, File.READ) != OK:
		return "cannot read " + path
	var rows = []
	var header = true
	while not file.eof_reached():
		var line = file.get_line().strip_edges()
		if line.empty():
			continue
		var fields = line.split(",")
		if header:
			header = false
			if not fields[0].is_valid_integer():
				continue
		rows.append([int(fields[0]), int(fields[1]), float(fields[2]), float(fields[3])])
	file.close()
	# The most common step between a person's consecutive frame numbers.
	var last_frame = {}
	var steps = {}
	for row in rows:
		if last_frame.has(row[1]):
			var step = row[0] - last_frame[row[1]]
			if step > 0:
				steps[step] = steps.get(step, 0) + 1
		last_frame[row[1]] = row[0]
	var best = 1
	for step in steps:
		if steps[step] > steps.get(best, 0):
			best = step
	var seconds_per_frame = 1.0 / (SAMPLE_RATE * best)
	for row in rows:
		var id = row[1]
		if not tracks.has(id):
			tracks[id] = {"times": [], "points": []}
		var time = row[0] * seconds_per_frame
		tracks[id].times.append(time)
		tracks[id].points.append(Vector2(row[2], row[3]))
		first_time = min(first_time, time)
		last_time = max(last_time, time)
	return "" if rows.size() > 0 else "no rows in " + path


# A track's point at `time`, or null outside its span.
static func sample(track, time):
	var times = track.times
	if time < times[0] or time > times[times.size() - 1]:
		return null
	var i = times.bsearch(time)
	if i <= 0:
		return track.points[0]
	var t0 = times[i - 1]
	var t1 = times[i]
	var f = 0.0 if t1 <= t0 else (time - t0) / (t1 - t0)
	return track.points[i - 1].linear_interpolate(track.points[i], f)


# The start of the `span` seconds with the most people at once (sampled every second).
func busiest_start(span):
	var best = first_time
	var most = -1
	var t = first_time
	while t + span <= last_time:
		var count = 0
		for id in tracks:
			if sample(tracks[id], t + span * 0.5) != null:
				count += 1
		if count > most:
			most = count
			best = t
		t += 2.0
	return best
