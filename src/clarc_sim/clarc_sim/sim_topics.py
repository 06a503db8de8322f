"""Topics between the simulated patient and the simulated devices (std_msgs/String JSON).
The robot side (clarc_agents.topics) never sees these: it only sees the devices."""

# patient -> microphone: {"text", "voice": [espeak-ng voice, words a minute, pitch]}
PATIENT_VOICE = "clarc/sim/patient/voice"
# patient -> microphone (latched, --audio): {"noise", "snr_db", "voice": [voice, wpm, pitch]}
ROOM = "clarc/sim/room"
PATIENT_TOUCH = "clarc/sim/patient/touch"  # patient -> touch screen: {"points"}
PATIENT_PRESENCE = "clarc/sim/patient/presence"  # patient -> Kinect (latched): {"present", "face"}
# patient -> Kinect (latched), in a Get Up & Go scenario: {"motion": {phase: s}, "go": epoch
# seconds the patient heard "go" (null before), "noise_mm", "drop_rate"}
PATIENT_TRIAL = "clarc/sim/patient/trial"
