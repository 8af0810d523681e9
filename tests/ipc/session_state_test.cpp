// The session's transition table (gport/ipc/session_state.hpp), without
// sockets: one test per event for what it does where it is legal and that it
// is refused where it is not, then the properties of the whole table.
#include "gport/ipc/session_state.hpp"

#include <gtest/gtest.h>

#include <array>
#include <optional>
#include <ostream>
#include <set>
#include <tuple>
#include <vector>

namespace gport::ipc {

// Failures print "open/reading/idle" (found by argument-dependent lookup).
void PrintTo(const SessionState& state, std::ostream* out) {
    *out << to_string(state);
}

namespace {

using E = SessionEvent;

constexpr std::array kLives{Life::kOpen, Life::kClosing, Life::kClosed};
constexpr std::array kInputs{Input::kIdle,   Input::kReading,   Input::kPosted,
                             Input::kPaused, Input::kThrottled, Input::kHungUp};
constexpr std::array kOutputs{Output::kIdle, Output::kWriting, Output::kWaiting};
constexpr std::array kEvents{E::kReadStarted, E::kReadDone,     E::kYielded,   E::kUnpaused,
                             E::kResumed,     E::kBacklogged,   E::kThrottled, E::kThrottleEnded,
                             E::kHungUp,      E::kRefused,      E::kClosed,    E::kWriteStarted,
                             E::kWritten,     E::kWaitWritable, E::kWritable};

SessionState at(Life life, Input input = Input::kIdle, Output output = Output::kIdle) {
    return {life, input, output};
}

std::vector<SessionState> all_states() {
    std::vector<SessionState> states;
    for (const auto life : kLives) {
        for (const auto input : kInputs) {
            for (const auto output : kOutputs) {
                states.push_back({life, input, output});
            }
        }
    }
    return states;
}

bool input_event(E event) {
    return event <= E::kHungUp;
}

bool output_event(E event) {
    return event >= E::kWriteStarted;
}

// An event on one side gives the same answer whatever the other side's state,
// so the tests below fix the other side at idle.
std::optional<SessionState> after(SessionState from, E event) {
    return transition(from, event);
}

void expect_refused(SessionState from, E event) {
    EXPECT_EQ(after(from, event), std::nullopt)
        << to_string(event) << " in " << to_string(from) << " should be refused";
}

void expect(SessionState from, E event, SessionState to) {
    EXPECT_EQ(after(from, event), std::optional(to))
        << to_string(event) << " in " << to_string(from) << " should give " << to_string(to);
}

// ---- input ----------------------------------------------------------------------

TEST(SessionState, ReadStartedReadsOnlyWhenOpenAndNothingElseIsPending) {
    expect(at(Life::kOpen), E::kReadStarted, at(Life::kOpen, Input::kReading));
    for (const auto input : {Input::kReading, Input::kPosted, Input::kPaused, Input::kThrottled}) {
        expect_refused(at(Life::kOpen, input), E::kReadStarted);
    }
    expect_refused(at(Life::kClosing), E::kReadStarted);
    expect_refused(at(Life::kClosed), E::kReadStarted);
}

TEST(SessionState, ReadDoneEndsTheReadInEveryLife) {
    for (const auto life : kLives) {
        expect(at(life, Input::kReading), E::kReadDone, at(life));  // an aborted read completes
        expect_refused(at(life, Input::kIdle), E::kReadDone);
    }
}

TEST(SessionState, YieldedPostsTheRestOnlyFromAnOpenIdleSession) {
    expect(at(Life::kOpen), E::kYielded, at(Life::kOpen, Input::kPosted));
    expect_refused(at(Life::kOpen, Input::kPosted), E::kYielded);  // never posted twice
    expect_refused(at(Life::kOpen, Input::kReading), E::kYielded);
    expect_refused(at(Life::kClosing), E::kYielded);
    expect_refused(at(Life::kClosed), E::kYielded);
}

TEST(SessionState, UnpausedPostsAPausedSessionUnlessItIsClosed) {
    expect(at(Life::kOpen, Input::kPaused), E::kUnpaused, at(Life::kOpen, Input::kPosted));
    // Refused after pausing (the idle timeout): its input still drains.
    expect(at(Life::kClosing, Input::kPaused), E::kUnpaused, at(Life::kClosing, Input::kPosted));
    expect_refused(at(Life::kClosed, Input::kPaused), E::kUnpaused);
    expect_refused(at(Life::kOpen, Input::kIdle), E::kUnpaused);
    expect_refused(at(Life::kOpen, Input::kPosted), E::kUnpaused);
}

TEST(SessionState, ResumedEndsThePostInEveryLife) {
    for (const auto life : kLives) {
        expect(at(life, Input::kPosted), E::kResumed, at(life));
        expect_refused(at(life, Input::kIdle), E::kResumed);
        expect_refused(at(life, Input::kPaused), E::kResumed);
    }
}

TEST(SessionState, BackloggedPausesOnlyAnOpenIdleSession) {
    expect(at(Life::kOpen), E::kBacklogged, at(Life::kOpen, Input::kPaused));
    expect_refused(at(Life::kOpen, Input::kPaused), E::kBacklogged);
    expect_refused(at(Life::kOpen, Input::kReading), E::kBacklogged);
    expect_refused(at(Life::kClosing), E::kBacklogged);
    expect_refused(at(Life::kClosed), E::kBacklogged);
}

TEST(SessionState, ThrottledWaitsForTheTimerOnlyFromAnOpenIdleSession) {
    expect(at(Life::kOpen), E::kThrottled, at(Life::kOpen, Input::kThrottled));
    expect_refused(at(Life::kOpen, Input::kThrottled), E::kThrottled);
    expect_refused(at(Life::kOpen, Input::kReading), E::kThrottled);
    expect_refused(at(Life::kClosing), E::kThrottled);
    expect_refused(at(Life::kClosed), E::kThrottled);
}

TEST(SessionState, ThrottleEndedEndsTheWaitInEveryLife) {
    for (const auto life : kLives) {
        expect(at(life, Input::kThrottled), E::kThrottleEnded, at(life));  // or was cancelled
        expect_refused(at(life, Input::kIdle), E::kThrottleEnded);
    }
}

TEST(SessionState, HungUpStopsInputAndClosesOnceTheRepliesAreWritten) {
    expect(at(Life::kOpen), E::kHungUp, at(Life::kClosing, Input::kHungUp));
    expect(at(Life::kOpen, Input::kIdle, Output::kWriting), E::kHungUp,
           at(Life::kClosing, Input::kHungUp, Output::kWriting));
    expect_refused(at(Life::kOpen, Input::kReading), E::kHungUp);  // EOF comes with read_done
    expect_refused(at(Life::kClosing), E::kHungUp);                // a refused client's EOF
    expect_refused(at(Life::kClosing, Input::kHungUp), E::kHungUp);
    expect_refused(at(Life::kClosed), E::kHungUp);
}

// ---- life -----------------------------------------------------------------------

TEST(SessionState, RefusedClosesAfterTheLastReplyAndLeavesWaitsToComplete) {
    for (const auto input :
         {Input::kIdle, Input::kReading, Input::kPosted, Input::kPaused, Input::kThrottled}) {
        for (const auto output : kOutputs) {
            expect(at(Life::kOpen, input, output), E::kRefused, at(Life::kClosing, input, output));
        }
    }
    expect_refused(at(Life::kClosing), E::kRefused);
    expect_refused(at(Life::kClosing, Input::kHungUp), E::kRefused);
    expect_refused(at(Life::kClosed), E::kRefused);
}

TEST(SessionState, ClosedIsReachedFromOpenOrClosingAndOnlyOnce) {
    for (const auto input : kInputs) {
        for (const auto output : kOutputs) {
            for (const auto life : {Life::kOpen, Life::kClosing}) {
                expect(at(life, input, output), E::kClosed, at(Life::kClosed, input, output));
            }
            expect_refused(at(Life::kClosed, input, output), E::kClosed);
        }
    }
}

// ---- output ---------------------------------------------------------------------

TEST(SessionState, WriteStartedOnlyWithNothingInFlightAndTheSocketOpen) {
    expect(at(Life::kOpen), E::kWriteStarted, at(Life::kOpen, Input::kIdle, Output::kWriting));
    expect(at(Life::kClosing, Input::kHungUp), E::kWriteStarted,
           at(Life::kClosing, Input::kHungUp, Output::kWriting));  // replies owed after EOF
    expect_refused(at(Life::kOpen, Input::kIdle, Output::kWriting), E::kWriteStarted);
    expect_refused(at(Life::kOpen, Input::kIdle, Output::kWaiting), E::kWriteStarted);
    expect_refused(at(Life::kClosed), E::kWriteStarted);
}

TEST(SessionState, WrittenEndsTheWriteInEveryLife) {
    for (const auto life : kLives) {
        expect(at(life, Input::kIdle, Output::kWriting), E::kWritten, at(life));
        expect_refused(at(life), E::kWritten);
        expect_refused(at(life, Input::kIdle, Output::kWaiting), E::kWritten);
    }
}

TEST(SessionState, WaitWritableOnlyWithNothingInFlightAndTheSocketOpen) {
    expect(at(Life::kOpen), E::kWaitWritable, at(Life::kOpen, Input::kIdle, Output::kWaiting));
    expect(at(Life::kClosing), E::kWaitWritable,
           at(Life::kClosing, Input::kIdle, Output::kWaiting));
    expect_refused(at(Life::kOpen, Input::kIdle, Output::kWaiting), E::kWaitWritable);
    expect_refused(at(Life::kOpen, Input::kIdle, Output::kWriting), E::kWaitWritable);
    expect_refused(at(Life::kClosed), E::kWaitWritable);
}

TEST(SessionState, WritableEndsTheWaitInEveryLife) {
    for (const auto life : kLives) {
        expect(at(life, Input::kIdle, Output::kWaiting), E::kWritable, at(life));
        expect_refused(at(life), E::kWritable);
        expect_refused(at(life, Input::kIdle, Output::kWriting), E::kWritable);
    }
}

// ---- the whole table ------------------------------------------------------------

TEST(SessionState, InputAndOutputAreIndependent) {
    for (const auto from : all_states()) {
        for (const auto event : kEvents) {
            const auto next = after(from, event);
            if (!next) {
                continue;
            }
            if (input_event(event)) {
                EXPECT_EQ(next->output, from.output) << to_string(event);
                auto other = from;
                for (const auto output : kOutputs) {  // same answer whatever the output
                    other.output = output;
                    const auto moved = after(other, event);
                    ASSERT_TRUE(moved) << to_string(event) << " in " << to_string(other);
                    EXPECT_EQ(moved->input, next->input);
                    EXPECT_EQ(moved->life, next->life);
                }
            }
            if (output_event(event)) {
                EXPECT_EQ(next->input, from.input) << to_string(event);
                EXPECT_EQ(next->life, from.life) << to_string(event);
                auto other = from;
                for (const auto input : kInputs) {  // same answer whatever the input
                    other.input = input;
                    const auto moved = after(other, event);
                    ASSERT_TRUE(moved) << to_string(event) << " in " << to_string(other);
                    EXPECT_EQ(moved->output, next->output);
                }
            }
        }
    }
}

// Every state the session can be in, walked from a new session.
std::set<std::tuple<Life, Input, Output>> reachable() {
    std::set<std::tuple<Life, Input, Output>> seen;
    std::vector<SessionState> todo{SessionState{}};
    while (!todo.empty()) {
        const auto s = todo.back();
        todo.pop_back();
        if (!seen.insert({s.life, s.input, s.output}).second) {
            continue;
        }
        for (const auto event : kEvents) {
            if (const auto next = after(s, event)) {
                todo.push_back(*next);
            }
        }
    }
    return seen;
}

TEST(SessionState, ANewSessionIsOpenWithNothingPending) {
    EXPECT_EQ(SessionState{}, at(Life::kOpen, Input::kIdle, Output::kIdle));
}

TEST(SessionState, AHungUpSessionIsNeverOpenAgainAndClosedIsFinal) {
    const auto states = reachable();
    for (const auto& [life, input, output] : states) {
        EXPECT_FALSE(input == Input::kHungUp && life == Life::kOpen);
        if (life != Life::kClosed) {
            continue;
        }
        for (const auto event : kEvents) {
            const auto next = after({life, input, output}, event);
            EXPECT_TRUE(!next || next->life == Life::kClosed);
            // Once closed, nothing new starts: only completions are legal.
            if (next) {
                EXPECT_TRUE(event == E::kReadDone || event == E::kResumed ||
                            event == E::kThrottleEnded || event == E::kWritten ||
                            event == E::kWritable)
                    << to_string(event);
            }
        }
    }
    // 3 lives x 6 inputs x 3 outputs, less what cannot happen: hung up
    // while open (3 states).
    EXPECT_EQ(states.size(), 3u * 6u * 3u - 3u);
}

TEST(SessionState, EveryEventIsLegalSomewhereReachable) {
    const auto states = reachable();
    for (const auto event : kEvents) {
        bool legal = false;
        for (const auto& [life, input, output] : states) {
            legal = legal || after({life, input, output}, event).has_value();
        }
        EXPECT_TRUE(legal) << to_string(event);
    }
}

// ---- the attacks' paths ---------------------------------------------------------

SessionState run(std::initializer_list<E> events) {
    SessionState s;
    for (const auto event : events) {
        const auto next = after(s, event);
        EXPECT_TRUE(next) << to_string(event) << " in " << to_string(s);
        if (!next) {
            break;
        }
        s = *next;
    }
    return s;
}

TEST(SessionState, AHalfClosingClientGetsItsRepliesThenCloses) {
    EXPECT_EQ(
        run({E::kReadStarted, E::kReadDone, E::kHungUp, E::kWriteStarted, E::kWritten, E::kClosed}),
        at(Life::kClosed, Input::kHungUp));
}

TEST(SessionState, ANeverReadingClientPausesAndIsRefusedWhilePaused) {
    const auto s =
        run({E::kReadStarted, E::kReadDone, E::kBacklogged, E::kWriteStarted, E::kRefused});
    EXPECT_EQ(s, at(Life::kClosing, Input::kPaused, Output::kWriting));
    expect_refused(s, E::kReadStarted);  // nothing more is read from it
    // It closes with the write still in flight (the queue overflowed); the
    // aborted write completes afterwards.
    EXPECT_EQ(after(*after(s, E::kClosed), E::kWritten), at(Life::kClosed, Input::kPaused));
}

TEST(SessionState, AFloodIsThrottledThenReadAgain) {
    EXPECT_EQ(run({E::kReadStarted, E::kReadDone, E::kYielded, E::kResumed, E::kThrottled,
                   E::kThrottleEnded, E::kReadStarted}),
              at(Life::kOpen, Input::kReading));
}

TEST(SessionState, ABatchThatClosesItsOwnSessionLeavesNothingToRefuse) {
    // A reply overflowed the queue while the batch ran: the session closed
    // in the middle of handling; the refusal that would follow is illegal
    // (close_after_reply checks), and so is reading on.
    const auto s = run({E::kReadStarted, E::kReadDone, E::kClosed});
    expect_refused(s, E::kRefused);
    expect_refused(s, E::kReadStarted);
    expect_refused(s, E::kHungUp);
}

TEST(SessionState, NamesAreThoseOfTheLog) {
    EXPECT_EQ(to_string(SessionState{}), "open/idle/idle");
    EXPECT_EQ(to_string(at(Life::kClosing, Input::kHungUp, Output::kWaiting)),
              "closing/hung_up/waiting");
    for (const auto event : kEvents) {
        EXPECT_NE(to_string(event), "?");
    }
    EXPECT_EQ(to_string(E::kThrottleEnded), "throttle_ended");
}

}  // namespace
}  // namespace gport::ipc
