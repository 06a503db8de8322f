"""Topic names between the CLARC agents and their devices (the stand-ins in clarc_sim, or real
hardware drivers that speak the same JSON). Relative, so they remap. std_msgs/String JSON, but
for the camera's images."""

SPEAKER_SAY = "clarc/speaker/say"  # Speech -> TTS: {"id", "text"}
SPEAKER_STOP = "clarc/speaker/stop"  # Speech -> TTS: {"id"}
SPEAKER = "clarc/speaker/events"  # TTS -> all: {"id", "text", "event": "start" | "end" | "stopped"}
# microphone + ASR -> Speech: {"text", "confidence" (0 to 1, optional), "start", "end" (epoch s,
# optional: when it was said)}
ASR = "clarc/asr"
# asr -> Speech: {"start" (epoch s)}: the patient began to speak (words may follow, once heard)
ASR_VOICE = "clarc/asr/voice"
# --audio: audio_common_msgs/AudioDataStamped, 16 kHz mono S16LE in 50 ms chunks (the stream's
# AudioInfo latched on <topic>/info): what the robot says (TTS), what the microphone hears
SPEAKER_AUDIO = "clarc/speaker/audio"
MICROPHONE_AUDIO = "clarc/microphone/audio"
# Panel -> touch screen (latched): {"sid", "text", "options", "option_points"} | {"clear": true}
PANEL_DISPLAY = "clarc/panel/display"
PANEL_TAP = "clarc/panel/tap"  # touch screen -> Panel: {"points", "text"}
# Kinect -> Person, every frame: {"present", "face": [x, y, z] mm}; a skeleton frame adds
# "stamp" (epoch seconds) and "skeleton": {joint: {"p": [x, y, z] mm, "c": confidence}}
KINECT_PERSON = "clarc/kinect/person"
# frames kept on each side of KINECT_PERSON (reliable): a minute of a 30 Hz sensor, so a robot
# that falls behind on a busy machine (at the fast pace, 300 frames a second of wall time) gets
# every frame late rather than loses one
KINECT_FRAMES_KEPT = 1800
# Kinect -> the camera agent: sensor_msgs/Image, colour (rgb8) and depth (16UC1, millimetres),
# frame_id "kinect", stamped when taken; best effort, the latest only (a camera's readers want
# the newest image, never a queue of old ones)
KINECT_RGB = "clarc/kinect/rgb"
KINECT_DEPTH = "clarc/kinect/depth"
PELEA_EVENTS = "clarc/pelea/events"  # PELEA -> dashboards: {"event", ...}
CGAMED_NOTIFY = "clarc/cgamed/notify"  # PELEA -> CGAmed: {"message"} for the clinician
CGAMED_NOTIFICATIONS = (
    "clarc/cgamed/notifications"  # CGAmed -> the clinician's phone: {"kind", "message", ...}
)
CGAMED_STORE = "clarc/cgamed/store_result"  # service dsr_msgs/srv/StoreResult
