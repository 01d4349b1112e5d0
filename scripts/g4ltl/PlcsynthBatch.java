/*
 * A headless driver for G4LTL (github.com/yyergg/g4ltl), written for plcsynth's
 * `bench ltl --compare-g4ltl`: it decides G4LTL-syntax files with G4LTL's own co-Büchi engine
 * and prints one machine-readable line per file. It is compiled at bench time against the G4LTL
 * classes the user points to; nothing of G4LTL is part of plcsynth.
 *
 * Usage: java -cp G4LTL_CLASSPATH:DIR g4ltl.PlcsynthBatch [--max-unroll K] [--timeout S] FILE...
 *
 * Output, one line per file, tab-separated:
 *   g4ltl <TAB> FILE <TAB> VERDICT <TAB> UNROLL <TAB> MILLISECONDS <TAB> NOTE
 * VERDICT is realizable, unrealizable, unknown (neither player won up to the largest unroll
 * depth), timeout or error; UNROLL the depth that decided (0 when none did); NOTE a short
 * reason for error, else empty.
 *
 * It lives in package g4ltl because G4LTL's file reading (SolverUtility) is package-private;
 * its public `synthesizeFromFile` cannot be used headless (it asks for the unsupported C
 * translator and ignores timers).
 */
package g4ltl;

import g4ltl.utility.ProblemDescription;
import g4ltl.utility.ResultLTLSynthesis;
import g4ltl.utility.SynthesisEngine;
import java.io.BufferedReader;
import java.io.File;
import java.io.InputStreamReader;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.concurrent.TimeUnit;

public class PlcsynthBatch {

    /** The prefix of the one line a child JVM prints for its file. */
    private static final String RESULT = "g4ltl\t";

    /** What G4LTL's engine says when a player has no strategy at this depth (anything else is an error). */
    private static final String NO_CONTROLLER = "Co-Buechi + safety game engine unable";

    public static void main(String[] args) throws Exception {
        int maxUnroll = 3;
        long timeoutSeconds = 60;
        boolean child = false;
        List<String> files = new ArrayList<>();
        for (int i = 0; i < args.length; i++) {
            switch (args[i]) {
                case "--max-unroll": maxUnroll = Integer.parseInt(args[++i]); break;
                case "--timeout": timeoutSeconds = Long.parseLong(args[++i]); break;
                // Internal: decide the one file in this JVM (the parent's timeout kills it).
                case "--child": child = true; break;
                default: files.add(args[i]);
            }
        }
        if (child) {
            decide(files.get(0), maxUnroll);
            return;
        }
        // One JVM per file: a runaway synthesis can only be stopped by killing its process,
        // and G4LTL keeps static state (BDD tables) that should not leak from file to file.
        String java = System.getProperty("java.home") + File.separator + "bin" + File.separator + "java";
        String classpath = System.getProperty("java.class.path");
        for (String file : files) {
            // G4LTL's formula translation and game search recurse deeply (SYNTCOMP's full_arbiter
            // overflows the default stack), so the child gets a large one.
            ProcessBuilder pb = new ProcessBuilder(java, "-Xss512m", "-cp", classpath, PlcsynthBatch.class.getName(),
                    "--child", "--max-unroll", String.valueOf(maxUnroll), file);
            pb.redirectErrorStream(true);
            Process p = pb.start();
            // Read the child's output on a thread, so a full pipe never blocks it.
            StringBuilder out = new StringBuilder();
            Thread reader = new Thread(() -> {
                try (BufferedReader r = new BufferedReader(new InputStreamReader(p.getInputStream(), StandardCharsets.UTF_8))) {
                    String line;
                    while ((line = r.readLine()) != null) {
                        synchronized (out) {
                            out.append(line).append('\n');
                        }
                    }
                } catch (Exception ignored) {
                    // the child was killed
                }
            });
            reader.start();
            if (!p.waitFor(timeoutSeconds, TimeUnit.SECONDS)) {
                p.destroyForcibly().waitFor();
                reader.join(1000);
                line(System.out, file, "timeout", 0, timeoutSeconds * 1000, "");
                continue;
            }
            reader.join();
            String result = null;
            String last = "";
            for (String l : out.toString().split("\n")) {
                if (l.startsWith(RESULT)) {
                    result = l;
                } else if (!l.isBlank()) {
                    last = l.trim();
                }
            }
            if (result != null) {
                System.out.println(result);
            } else {
                line(System.out, file, "error", 0, 0, "exit " + p.exitValue() + ": " + last);
            }
            System.out.flush();
        }
    }

    /** Decides one file as G4LTL's GUI does (GUI.jButtonSynthesizeActionPerformed, monolithic). */
    private static void decide(String file, int maxUnroll) {
        PrintStream out = System.out;
        // G4LTL prints its progress to standard output; only the result line may go there.
        System.setOut(new PrintStream(OutputStream.nullOutputStream()));
        long started = System.nanoTime();
        try {
            HashMap<String, String> map = SolverUtility.getLTLSpecificationFromFile(new File(file));
            StringBuilder input = new StringBuilder(map.get(SolverUtility.INPUT));
            StringBuilder output = new StringBuilder(map.get(SolverUtility.OUTPUT));
            String timers = map.get(SolverUtility.TIMER);
            StringBuilder spec = new StringBuilder(map.get(SolverUtility.LTL));
            if (!timers.isEmpty()) {
                // The GUI's timer encoding: `t.start`/`t.expire` become signals `t_start`/`t_expire`,
                // with the paper's antecedent that a started timer expires.
                spec = new StringBuilder(spec.toString().replace(".", "_"));
                for (String timer : SolverUtility.getSignals(timers)) {
                    String name = timer.trim().split("\\(")[0];
                    spec.append("ASSUME ALWAYS (" + name + "_start -> NEXT EVENTUALLY " + name + "_expire)\n");
                    input.append(", " + name + "_expire");
                    output.append(", " + name + "_start");
                }
            }
            String ltl = SolverUtility.parseLTLspecification(SolverUtility.changeSpecToInternalFormat(spec.toString()));
            for (int unroll = 1; unroll <= maxUnroll; unroll++) {
                // The controller first, then the environment, as plcsynth plays them for each k.
                for (boolean controller : new boolean[] {true, false}) {
                    ProblemDescription prob = new ProblemDescription(SolverUtility.getSignals(input.toString()),
                            SolverUtility.getSignals(output.toString()), SolverUtility.getSignals(timers), ltl, unroll);
                    ResultLTLSynthesis r = new SynthesisEngine().invokeMonolithicCoBuechiEngine(prob, true,
                            SynthesisEngine.OUTPUT_PSUEDO_CODE, controller);
                    if (r.isStrategyFound()) {
                        line(out, file, controller ? "realizable" : "unrealizable", unroll, millis(started), "");
                        return;
                    }
                    String message = r.getMessage1();
                    if (message == null || !message.startsWith(NO_CONTROLLER)) {
                        // The engine caught an exception (a parse error of the formula, say) and
                        // returned its stack trace as the message.
                        String first = message == null ? "no message" : message.split("\n")[0].trim();
                        line(out, file, "error", 0, millis(started), first);
                        return;
                    }
                }
            }
            line(out, file, "unknown", 0, millis(started), "");
        } catch (Throwable e) {
            line(out, file, "error", 0, millis(started), e.toString());
        }
    }

    private static long millis(long started) {
        return (System.nanoTime() - started) / 1_000_000;
    }

    private static void line(PrintStream out, String file, String verdict, int unroll, long ms, String note) {
        String clean = note.replace('\t', ' ').replace('\n', ' ');
        out.println(RESULT + file + "\t" + verdict + "\t" + unroll + "\t" + ms + "\t" + clean);
        out.flush();
    }
}
