// The field list of the status result's "counters" object (docs/api.md,
// "status"), in the order gportd writes them: the one list that gportd's
// core counts into (daemon::Counters), ipc writes as JSON and
// libgport-client reads back (client::Counters). Every counter is an
// unsigned 64-bit count since gportd started.
//
// ABI: libgport-client's Counters is made from this list, so adding or
// reordering a field changes that installed struct's layout and bumps the
// library's SOVERSION (client/CMakeLists.txt); tests/contract pins the
// layout of SOVERSION 1.
//
// Standard C++17, installed with libgport-client's headers.
#pragma once

// X(name) for each counter the core keeps:
//   frames_in, bytes_in, frames_out, bytes_out: frames and bytes read from
//     and written to the device;
//   attitude_frames: 0x87 frames read;
//   crc_errors, header_errors, garbage_bytes, resyncs: the decoder's
//     rejects (docs/protocol.md);
//   bad_messages: valid frames whose content made no sense;
//   device_opens, device_failures: opens, and failed opens and lost devices;
//   keepalive_frames: speed frames re-sent by the keepalive;
//   motion_updates: speeds, angles, centres that updated their owner's motion;
//   stops_sent: zero-speed frames written to the device;
//   frames_replaced: waiting 0x85 frames a newer 0x85 replaced;
//   frames_refused: camera/settings frames refused because the device is stuck;
//   settings_timeouts: settings requests the gimbal did not answer.
#define GPORT_CONTRACT_CORE_COUNTERS(X) \
    X(frames_in)                        \
    X(bytes_in)                         \
    X(frames_out)                       \
    X(bytes_out)                        \
    X(attitude_frames)                  \
    X(crc_errors)                       \
    X(header_errors)                    \
    X(garbage_bytes)                    \
    X(resyncs)                          \
    X(bad_messages)                     \
    X(device_opens)                     \
    X(device_failures)                  \
    X(keepalive_frames)                 \
    X(motion_updates)                   \
    X(stops_sent)                       \
    X(frames_replaced)                  \
    X(frames_refused)                   \
    X(settings_timeouts)

// Every field of "counters": the core's, then the one the transport keeps,
// dropped_notifications (attitude notifications dropped for slow clients).
#define GPORT_CONTRACT_COUNTERS(X) GPORT_CONTRACT_CORE_COUNTERS(X) X(dropped_notifications)
